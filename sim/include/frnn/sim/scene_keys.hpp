// One key of a scene by its path, named as the scene parser names keys in its messages:
// "domain.max", "colliders[0].center", "particles.2d", "sph.alpha". A key is set as a scene
// file would set it: the scene is written as JSON (scene_to_json), the value put at the path
// and the JSON parsed again, so the parser's checks and messages are the only rules. The
// viewer's panel and scripts edit scenes through it.
//
// Complexity: O(size of the scene's JSON) per call. Thread safety: reentrant.
#pragma once
#include <string>
#include <string_view>
#include <vector>

#include "frnn/sim/scene.hpp"

namespace frnn::sim {

/// The values a key takes when it is one of a list (the solver, a fluid block's or collider's
/// type, a choice of the parameter table); empty for every other key.
std::vector<std::string> scene_key_choices(std::string_view path);

/// `s` with the key at `path` set to `value` (JSON text). `path` names a key that
/// scene_to_json(s) writes, a leaf or an object or array. Throws frnn::error starting with
/// `origin` and naming the path when there is no such key, the value is not JSON or the parser
/// rejects the result. A fluid block or collider given another "type" keeps its place and size:
/// a box becomes the sphere inscribed in it, a sphere the box around it, a plane keeps its
/// point as the new shape's center.
scene with_scene_key(const scene& s, std::string_view path, std::string_view value, const std::string& origin);

}  // namespace frnn::sim
