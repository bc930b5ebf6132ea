// MJCF <contact>: explicit <pair>s and <exclude>d body pairs.
#include <algorithm>

#include "mjcf_internal.h"
#include "pliant/core/error.h"

namespace pliant::articulated::mjcf_internal {
namespace {

// <contact><pair geom1 geom2 [friction] [margin] [condim]>: an explicit pair
// (Model::contact_pairs), friction's first (sliding) value its Coulomb coefficient,
// margin its activation distance, condim 1 (frictionless), 3 (the default), 4 / 6
// (+ torsional / rolling friction); solref/solimp/gap rejected.
void read_contact_pair(Ctx& c, const XmlElement& e, const std::string& path) {
  check_attrs(c, e, path, {"name", "geom1", "geom2", "friction", "condim", "margin"});
  ContactPair pair;
  int* ids[2] = {&pair.geom1, &pair.geom2};
  const char* keys[2] = {"geom1", "geom2"};
  for (int i = 0; i < 2; ++i) {
    const auto* name = e.attr(keys[i]);
    if (!name) throw InputError(c.file, path + "/@" + keys[i], "<pair> needs geom1 and geom2");
    std::string why;
    *ids[i] = geom_named(c.m, *name, &why);
    if (*ids[i] < 0) throw InputError(c.file, path + "/@" + keys[i], why);
  }
  const std::string problem = contact_pair_problem(c.m, pair.geom1, pair.geom2);
  if (!problem.empty()) throw InputError(c.file, path + "/@geom2", problem);
  if (e.attr("friction")) {
    // MuJoCo's five: slide1 slide2 torsion roll1 roll2 (one sliding and one rolling
    // coefficient used: isotropic friction); values not given keep MuJoCo's defaults.
    const auto f = numbers(c, e, path, "friction", 1, 5);
    for (double v : f)
      if (v < 0) throw InputError(c.file, path + "/@friction", "must be >= 0");
    pair.mu = f[0];
    if (f.size() > 2) pair.torsion = f[2];
    if (f.size() > 3) pair.roll = f[3];
  }
  pair.margin = number(c, e, path, "margin", 0, 0);
  if (e.attr("condim")) {
    const double cd = numbers(c, e, path, "condim", 1, 1)[0];
    const std::string problem = contact_pair_condim_problem(cd);
    if (!problem.empty()) throw InputError(c.file, path + "/@condim", problem);
    pair.frictionless = cd == 1;
    pair.condim = static_cast<int>(cd);
  }
  c.m.contact_pairs.push_back(pair);
}

}  // namespace

// <contact>: <exclude body1 body2> (body pairs that never touch) and <pair>; anything
// else rejected.
void read_contact(Ctx& c, const XmlElement& e, const std::string& path) {
  check_attrs(c, e, path, {});
  for (size_t k = 0; k < e.children.size(); ++k) {
    const XmlElement& ch = e.children[k];
    const std::string cp = child_path(path, e, k);
    if (ch.name == "pair") {
      read_contact_pair(c, ch, cp);
      continue;
    }
    if (ch.name != "exclude")
      throw InputError(c.file, cp, "unsupported element <" + ch.name + "> in <contact> (only <exclude> and <pair> are supported)");
    check_attrs(c, ch, cp, {"name", "body1", "body2"});
    int ids[2];
    const char* keys[2] = {"body1", "body2"};
    for (int i = 0; i < 2; ++i) {
      const auto* name = ch.attr(keys[i]);
      if (!name) throw InputError(c.file, cp + "/@" + keys[i], "<exclude> needs body1 and body2");
      std::string why;
      ids[i] = body_named(c.m, *name, &why);
      if (ids[i] < 0)
        throw InputError(c.file, cp + "/@" + keys[i],
                         why + (*name == "world" ? " (excluding the world's obstacles is not supported)" : ""));
    }
    if (ids[0] == ids[1]) throw InputError(c.file, cp + "/@body2", "a body cannot be excluded from itself");
    c.m.contact_exclude.push_back({std::min(ids[0], ids[1]), std::max(ids[0], ids[1])});
  }
}

}  // namespace pliant::articulated::mjcf_internal
