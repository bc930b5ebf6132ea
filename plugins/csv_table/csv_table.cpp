// Pliant plugin: exporter "csv" writes OUT/frames.csv, one row per frame with the
// frame index, its time and every small field flattened into columns: a field of
// one value is the column `name`, a field of shape [n] the columns `name[0]` ..
// `name[n-1]`, [n, m] `name[i][j]`. Small means at most kMaxValues values in every
// frame that has it and the same shape in all of them; larger or varying fields
// (images, meshes, contact lists) are left out and named in the host's log. A frame
// without one of the columns' fields leaves its cells empty. This is the table to
// plot from: an articulated take's `energy` is (kinetic, potential, total) in J and
// `body_pose[b]` (x, y, z, qw, qx, qy, qz) per body.
//
// Rows are kept until the last frame (the columns are known only then) and the file
// is written under a temporary name and renamed, so no half table is ever left.
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "pliant/plugin.h"
#include "pliant/plugin_support.h"

PLIANT_PLUGIN_DECLARE_API_VERSION();

namespace {

using pliant_plugin::fail;
using pliant_plugin::write_file_atomically;

constexpr size_t kMaxValues = 256;

struct Column {
  std::vector<uint32_t> shape;
  bool kept = true;  // false once the field is too large or changes shape
  std::string why;   // the reason it was left out
};

struct Row {
  int32_t index;
  double time_s;
  std::map<std::string, std::vector<float>> values;
};

struct CsvExport {
  std::filesystem::path out_dir;
  std::map<std::string, Column> columns;
  std::vector<std::string> order;  // fields in the order they first appear: the column order
  std::vector<Row> rows;
};
CsvExport g_export;
// The host's log function, copied at load (the PliantHost struct is only lent for that call).
void (*g_log)(const char* level, const char* message) = nullptr;

size_t value_count(const std::vector<uint32_t>& shape) {
  size_t n = 1;
  for (uint32_t d : shape) n *= d;
  return n;
}

std::string shape_text(const std::vector<uint32_t>& shape) {
  std::string s = "[";
  for (size_t i = 0; i < shape.size(); ++i) {
    if (i) s += 'x';
    s += std::to_string(shape[i]);
  }
  return s + "]";
}

// The column names of one field, flattened slowest index first.
void append_names(const std::string& name, const std::vector<uint32_t>& shape, std::vector<std::string>& out) {
  const size_t n = value_count(shape);
  if (n == 1 && shape.size() <= 1) {
    out.push_back(name);
    return;
  }
  for (size_t k = 0; k < n; ++k) {
    std::string s = name;
    size_t rest = k, stride = n;
    for (uint32_t d : shape) {
      stride /= d;
      s += '[';
      s += std::to_string(rest / stride);
      s += ']';
      rest %= stride;
    }
    out.push_back(s);
  }
}

int csv_begin(void*, const char* out_dir, const char*, uint32_t frame_count, char* err, size_t err_size) {
  g_export = CsvExport{};
  g_export.out_dir = out_dir;
  g_export.rows.reserve(frame_count);
  return pliant_plugin::create_output_dir(out_dir, err, err_size);
}

int csv_frame(void*, const PliantFrame* frame, char*, size_t) {
  Row row{frame->index, frame->time_s, {}};
  for (uint32_t f = 0; f < frame->field_count; ++f) {
    const PliantField& field = frame->fields[f];
    const std::vector<uint32_t> shape(field.shape, field.shape + field.ndim);
    const size_t n = value_count(shape);
    auto [it, inserted] = g_export.columns.try_emplace(field.name, Column{shape, true, ""});
    if (inserted) g_export.order.push_back(field.name);
    Column& c = it->second;
    if (!c.kept) continue;
    if (n > kMaxValues) {
      c.kept = false;
      c.why = shape_text(shape) + " in frame " + std::to_string(frame->index) + ": over " +
              std::to_string(kMaxValues) + " values";
    } else if (c.shape != shape) {
      c.kept = false;
      c.why = shape_text(c.shape) + ", then " + shape_text(shape) + " in frame " + std::to_string(frame->index);
    } else {
      row.values[field.name].assign(field.data, field.data + n);
    }
  }
  g_export.rows.push_back(std::move(row));
  return 0;
}

int csv_end(void*, char* err, size_t err_size) {
  std::vector<std::pair<std::string, size_t>> fields;  // kept fields and their value counts
  std::vector<std::string> names;
  std::string skipped;
  for (const std::string& f : g_export.order) {
    const Column& c = g_export.columns[f];
    if (c.kept) {
      fields.emplace_back(f, value_count(c.shape));
      append_names(f, c.shape, names);
    } else {
      if (!skipped.empty()) skipped += "; ";
      skipped += f + " " + c.why;
    }
  }
  if (fields.empty() && !g_export.rows.empty())
    return fail(err, err_size, "no field of at most %zu values with one shape in every frame to tabulate (%s)",
                kMaxValues, skipped.c_str());
  if (!skipped.empty() && g_log) g_log("warn", ("csv: left out " + skipped).c_str());

  const std::filesystem::path path = g_export.out_dir / "frames.csv";
  const int rc = write_file_atomically(
      path,
      [&](std::FILE* file) {
        bool ok = std::fputs("frame,time_s", file) >= 0;
        for (const std::string& n : names) ok = ok && std::fprintf(file, ",%s", n.c_str()) > 0;
        ok = ok && std::fputc('\n', file) != EOF;
        for (const Row& r : g_export.rows) {
          ok = ok && std::fprintf(file, "%d,%.9g", int(r.index), r.time_s) > 0;
          for (const auto& [f, n] : fields) {
            const auto v = r.values.find(f);
            for (size_t k = 0; k < n; ++k)
              ok = ok && (v == r.values.end() ? std::fputc(',', file) != EOF
                                              : std::fprintf(file, ",%.9g", double(v->second[k]) + 0.0) > 0);
          }
          ok = ok && std::fputc('\n', file) != EOF;
        }
        return ok;
      },
      err, err_size);
  g_export = CsvExport{};
  return rc;
}

}  // namespace

PLIANT_PLUGIN_EXPORT int pliant_plugin_load(const PliantHost* host, PliantRegistry* registry) {
  g_log = host ? host->log : nullptr;
  return pliant_plugin::register_exporter(
      registry, "csv", "one table of every frame's small fields (energy, body poses) for plotting: frames.csv",
      ".csv", csv_begin, csv_frame, csv_end);
}
