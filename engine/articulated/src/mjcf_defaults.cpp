// MJCF <default> classes: reading them (nested, inherited) and applying them to elements.
#include "mjcf_internal.h"
#include "pliant/core/error.h"
#include "pliant/core/json_reader.h"

namespace pliant::articulated::mjcf_internal {
namespace {

void merge_attrs(std::vector<std::pair<std::string, std::string>>& into,
                 const std::vector<std::pair<std::string, std::string>>& from) {
  for (const auto& [k, v] : from) {
    bool found = false;
    for (auto& kv : into)
      if (kv.first == k) kv.second = v, found = true;
    if (!found) into.emplace_back(k, v);
  }
}

}  // namespace

void read_default(const Ctx& c, const XmlElement& e, const std::string& path, const std::string& parent,
                  bool top, Defaults* d) {
  for (const auto& [k, v] : e.attrs)
    if (k != "class") throw InputError(c.file, path + "/@" + k, "unsupported attribute of <default>");
  std::string cls = "main";
  if (const auto* n = e.attr("class")) cls = *n;
  else if (!top) throw InputError(c.file, path + "/@class", "a nested <default> needs a class");
  if (d->count(cls) && !(top && cls == "main")) throw InputError(c.file, path + "/@class", "class \"" + cls + "\" defined twice");
  (*d)[cls] = parent.empty() ? std::map<std::string, std::vector<std::pair<std::string, std::string>>>{} : (*d)[parent];
  for (size_t k = 0; k < e.children.size(); ++k) {
    const XmlElement& ch = e.children[k];
    const std::string p = child_path(path, e, k);
    if (ch.name == "default") {
      read_default(c, ch, p, cls, false, d);
    } else if (ch.name == "joint" || ch.name == "geom" || ch.name == "motor" || ch.name == "mesh") {
      for (const auto& [key, v] : ch.attrs)
        if (key == "class" || key == "name") throw InputError(c.file, p + "/@" + key, "not allowed in a default");
      merge_attrs((*d)[cls][ch.name], ch.attrs);
    } else if (ch.name == "site" || ch.name == "camera" || ch.name == "light" || ch.name == "material") {
      continue;  // visual only
    } else {
      throw InputError(c.file, p, "unsupported element <" + ch.name + "> in <default> (supported: joint, geom, motor, mesh)");
    }
  }
}

namespace {

void check_class(const Ctx& c, const std::string& name, const std::string& attr_path, const Defaults& d) {
  if (d.count(name)) return;
  std::vector<std::string> names;
  for (const auto& kv : d) names.push_back(kv.first);
  const std::string near = nearest_name(name, names);
  throw InputError(c.file, attr_path,
                   "no default class \"" + name + "\"" + (near.empty() ? "" : "; did you mean \"" + near + "\"?"));
}

}  // namespace

// Rewrites joint/geom/motor/mesh elements with their class's attributes under their own.
void apply_defaults(const Ctx& c, XmlElement& e, const std::string& path, const Defaults& d,
                    const std::string& cls) {
  std::string child_cls = cls;
  if (e.name == "body") {
    if (const auto* n = e.attr("childclass")) {
      check_class(c, *n, path + "/@childclass", d);
      child_cls = *n;
    }
  }
  if (e.name == "joint" || e.name == "geom" || e.name == "motor" || e.name == "mesh") {
    std::string own = cls;
    if (const auto* n = e.attr("class")) {
      check_class(c, *n, path + "/@class", d);
      own = *n;
    }
    auto merged = std::vector<std::pair<std::string, std::string>>{};
    const auto it = d.find(own);
    if (it != d.end()) {
      const auto el = it->second.find(e.name);
      if (el != it->second.end()) merged = el->second;
    }
    std::vector<std::pair<std::string, std::string>> own_attrs;
    for (const auto& kv : e.attrs)
      if (kv.first != "class") own_attrs.push_back(kv);
    merge_attrs(merged, own_attrs);
    e.attrs = merged;
  }
  std::vector<std::pair<std::string, std::string>> kept;
  for (const auto& kv : e.attrs)
    if (!(e.name == "body" && kv.first == "childclass")) kept.push_back(kv);
  e.attrs = kept;
  for (size_t k = 0; k < e.children.size(); ++k)
    apply_defaults(c, e.children[k], child_path(path, e, k), d, child_cls);
}

}  // namespace pliant::articulated::mjcf_internal
