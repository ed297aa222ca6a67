// The vector directory (vectors/data): generation and verification of all
// three levels. Layout:
//   DIR/index.json           the files, their levels and test counts
//   DIR/arithmetic.json      level 1 (lockstep/vectors/arithmetic.hpp)
//   DIR/formulas.json        level 2 (lockstep/vectors/formulas.hpp)
//   DIR/scenes/<name>.json   level 3, one per built-in scene (lockstep/vectors/scenes.hpp)
#pragma once
#include <map>
#include <ostream>
#include <string>
#include <vector>

#include "lockstep/vectors/common.hpp"
#include "lockstep/vectors/scenes.hpp"

namespace lockstep::vectors {

// The command that regenerates the checked-in vectors (for messages).
inline constexpr const char* kRegenerateCommand = "lockstep vectors generate vectors/data";

struct GenerateOptions {
  std::vector<std::string> scenes;  // empty: every built-in scene
  SceneVectorOptions scene;
};

// Writes every file and DIR/index.json (creating DIR and DIR/scenes); returns
// the files written (relative to DIR). Progress lines go to *log if given.
// The output depends only on the engine's bits: regenerating an unchanged
// engine rewrites identical files.
std::vector<std::string> generate_directory(const std::string& dir, const GenerateOptions& options, std::ostream* log);

struct VerifyOptions {
  bool arithmetic = true;
  bool formulas = true;
  bool scenes = true;
  std::vector<std::string> only_scenes;   // empty: every scene file in the index
  std::map<std::string, int> max_frames;  // per scene: verify frames 0..N only
};

// Verifies the files listed in DIR/index.json (and that every built-in scene
// has a file when all scenes are verified). One verdict per file, in index order.
std::vector<Verdict> verify_directory(const std::string& dir, const VerifyOptions& options, std::ostream* log);

// The source tree this library was built from (for `lockstep certify`, which
// runs vectors/certify/certify.py there).
std::string source_dir();

}  // namespace lockstep::vectors
