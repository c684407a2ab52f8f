// Scene files (docs/scene-format.md) to Scene (scene.h).
#pragma once

#include <string>
#include <string_view>

#include "common/scene.h"

namespace weft::scenes {

// Parses a scene file's text. Relative asset paths are resolved against `base_dir` (the scene
// file's folder). Unknown keys, wrong types, non-finite or out-of-range numbers are errors: returns
// the message (empty on success), and `out` is only written on success.
std::string parse_scene(std::string_view json_text, const std::string& base_dir, Scene* out);

// Reads and parses a scene file.
std::string load_scene_file(const std::string& path, Scene* out);

}  // namespace weft::scenes
