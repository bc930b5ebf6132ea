#include "golden.h"

#include <cstdlib>
#include <filesystem>

#include "render/screenshot.h"

namespace pliant::test {
namespace fs = std::filesystem;

bool updating_goldens() {
  const char* v = std::getenv("PLIANT_UPDATE_GOLDEN");
  return v != nullptr && std::string(v) == "1";
}

namespace {
void make_parent(const std::string& path) {
  const fs::path parent = fs::path(path).parent_path();
  std::error_code ec;
  if (!parent.empty()) fs::create_directories(parent, ec);
}

std::string actual_path_for(const std::string& diff_path) {
  fs::path p(diff_path);
  return (p.parent_path() / (p.stem().string() + "_actual.png")).string();
}
}  // namespace

::testing::AssertionResult matches_golden(const editor::Image& image, const std::string& golden_path,
                                          const std::string& diff_path, int max_tol, double mean_tol) {
  std::string err;
  if (updating_goldens()) {
    make_parent(golden_path);
    if (!editor::write_png(golden_path, image, &err))
      return ::testing::AssertionFailure() << "updating golden: " << err;
    return ::testing::AssertionSuccess() << "golden written: " << golden_path;
  }
  const editor::Image golden = editor::read_png(golden_path, &err);
  make_parent(diff_path);
  const std::string actual_path = actual_path_for(diff_path);
  if (golden.empty()) {
    editor::write_png(actual_path, image);
    return ::testing::AssertionFailure() << "golden image missing or unreadable: " << err
                                         << "\n  actual written to " << actual_path
                                         << "\n  (re)generate goldens with PLIANT_UPDATE_GOLDEN=1";
  }
  const editor::CompareResult r = editor::compare(image, golden, max_tol, mean_tol);
  if (r.pass) return ::testing::AssertionSuccess() << r.message;
  editor::write_png(actual_path, image);
  auto fail = ::testing::AssertionFailure();
  fail << "image differs from golden " << golden_path << ": " << r.message << "\n  actual: " << actual_path;
  if (!r.size_mismatch && editor::write_png(diff_path, editor::diff_image(image, golden, max_tol), &err))
    fail << "\n  diff:   " << diff_path;
  return fail;
}

}  // namespace pliant::test
