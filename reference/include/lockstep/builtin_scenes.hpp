// The built-in scenes (docs/SCENES.md describes each).
//
// Every built-in scene is built from literal constants and integer arithmetic
// (plus correctly rounded IEEE + - * / and sqrt for the SDF volumes), so it is
// the same bit for bit on every platform. Orientations are given as literal,
// not necessarily normalised, quaternions; the engine normalises them on load.
#pragma once
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "lockstep/scene.hpp"

namespace lockstep {

inline constexpr const char* kDefaultSceneName = "drop";

// drop, bounce, slide, tip_edge, tip_corner, stack5, pyramid, pile1000, bowl,
// terrain: always in this order.
std::vector<std::string> builtin_scene_names();

// The scene of that name (its Scene::name is the same), or nullopt.
std::optional<Scene> builtin_scene(std::string_view name);

}  // namespace lockstep
