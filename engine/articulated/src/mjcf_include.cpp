// MJCF <include file="..."/>: MuJoCo's meta-element, expanded before anything is read.
// Wherever it appears it is replaced by the children of the included file's top-level
// element; file names are relative to the main model file's folder (MuJoCo 2.2.2);
// includes nest, and a file may be included once in the whole model, as MuJoCo
// requires. Element paths in later errors are those of the expanded document.
#include <fstream>
#include <set>
#include <sstream>

#include "mjcf_internal.h"
#include "pliant/core/error.h"
#include "xml.h"

namespace pliant::articulated::mjcf_internal {
namespace {

void expand(Ctx& c, XmlElement& e, const std::string& path, const std::filesystem::path& base_dir,
            std::set<std::string>* seen) {
  int expanded = 0;  // includes of e replaced so far: an include's path counts them (as written)
  for (size_t k = 0; k < e.children.size();) {
    XmlElement& ch = e.children[k];
    if (ch.name != "include") {
      expand(c, ch, child_path(path, e, k), base_dir, seen);
      ++k;
      continue;
    }
    const std::string p = path + "/include[" + std::to_string(expanded++) + "]";
    check_attrs(c, ch, p, {"file"});
    const std::string* name = ch.attr("file");
    if (!name || name->empty()) throw InputError(c.file, p + "/@file", "include needs file=\"<MJCF file>\"");
    const std::filesystem::path file = base_dir / *name;
    std::error_code ec;
    const std::filesystem::path canonical = std::filesystem::weakly_canonical(file, ec);
    const std::string key = ec ? file.string() : canonical.string();
    if (!seen->insert(key).second)
      throw InputError(c.file, p + "/@file", "\"" + *name + "\" is included more than once (MuJoCo allows a file once per model)");
    std::ifstream in(file, std::ios::binary);
    if (!in) throw InputError(c.file, p + "/@file", "cannot read included file " + file.string());
    std::stringstream ss;
    ss << in.rdbuf();
    XmlElement root = parse_xml(ss.str(), file.string());
    if (root.children.empty())
      throw InputError(c.file, p + "/@file", "included file " + file.string() + " has nothing below its <" + root.name + ">");
    std::vector<XmlElement> inserted = std::move(root.children);
    e.children.erase(e.children.begin() + static_cast<long>(k));
    e.children.insert(e.children.begin() + static_cast<long>(k), std::make_move_iterator(inserted.begin()),
                      std::make_move_iterator(inserted.end()));
    // The inserted elements are looked at next: their own includes expand in place.
  }
}

}  // namespace

void expand_includes(Ctx& c, XmlElement& root, const std::filesystem::path& base_dir) {
  std::set<std::string> seen;
  expand(c, root, "/" + root.name, base_dir, &seen);
}

}  // namespace pliant::articulated::mjcf_internal
