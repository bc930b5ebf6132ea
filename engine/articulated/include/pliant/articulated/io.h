// Loading models: Pliant JSON (bodies with joints, geoms, inertials; or a chain
// generator) and a subset of MuJoCo's MJCF (mujoco/compiler/option/worldbody/body/
// joint/freejoint/geom/inertial/actuator motor). Every problem is an InputError
// naming the file and the JSON pointer or the XML element path
// (e.g. /mujoco/worldbody/body[0]/geom[1]/@size).
#pragma once
#include <filesystem>
#include <string>

#include "pliant/articulated/model.h"
#include "pliant/core/json_reader.h"

namespace pliant::articulated {

// Mesh files (<asset><mesh file=.../>) are read relative to base_dir (the MJCF
// file's folder; compiler meshdir is appended).
Model model_from_mjcf(const std::string& text, const std::string& file,
                      const std::filesystem::path& base_dir = {});
Model model_from_json(JsonReader& r);
// .xml -> MJCF, .json -> Pliant JSON model (the whole document is the model).
Model model_load_file(const std::filesystem::path& path, const std::string& label);

}  // namespace pliant::articulated
