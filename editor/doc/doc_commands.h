// File commands on a Document: new, open, save, save as. They return an error
// message ("" on success) instead of throwing, and never lose the current
// document on failure.
#pragma once
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "doc/document.h"

namespace pliant::editor {

// The built-in template (a small 2D plume) used when the default scene file is missing.
nlohmann::json builtin_scene_template();
// assets/scenes/plume_2d.json found beside the binary or in the source tree, or "".
std::filesystem::path default_scene_path();

// New document from the default scene (unsaved, no path).
void new_document(Document& doc);
// Validates with pliant::load_scene; on InputError returns its message and
// leaves doc untouched.
std::string open_document(Document& doc, const std::filesystem::path& path);
std::string save_document(Document& doc);  // error if it has no path
std::string save_document_as(Document& doc, const std::filesystem::path& path);

// Checks the scene like a job would (envelope, then the kind's compile step);
// returns the error message or "".
std::string validate_scene(const nlohmann::json& scene, const std::filesystem::path& path);

}  // namespace pliant::editor
