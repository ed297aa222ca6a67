// Replays files through the fuzz function (scene_fuzz_one.hpp) with the normal
// toolchain, so CI checks the corpus without clang's libFuzzer:
//   scene_replay [--expect-rejected] PATH...
// PATH is a file or a directory (its regular files, recursively, in sorted
// order; files named README*, EXPECTED* or *.md are skipped). With
// --expect-rejected every file must be refused with a SceneError (the
// handwritten bad scenes). Prints one line per file and a summary; exits 1 on
// any finding or unmet expectation, 2 on a usage error.
#include <algorithm>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "scene_fuzz_one.hpp"

namespace fs = std::filesystem;
using lockstep::fuzz::Outcome;

namespace {

bool skipped(const fs::path& p) {
  const std::string name = p.filename().string();
  return name.rfind("README", 0) == 0 || name.rfind("EXPECTED", 0) == 0 || p.extension() == ".md" ||
         name.empty() || name[0] == '.';
}

std::vector<fs::path> collect(const fs::path& root) {
  std::vector<fs::path> files;
  if (fs::is_regular_file(root)) {
    files.push_back(root);
  } else if (fs::is_directory(root)) {
    for (const auto& e : fs::recursive_directory_iterator(root))
      if (e.is_regular_file() && !skipped(e.path())) files.push_back(e.path());
    std::sort(files.begin(), files.end());
  }
  return files;
}

}  // namespace

int main(int argc, char** argv) {
  bool expect_rejected = false;
  std::vector<fs::path> roots;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--expect-rejected") expect_rejected = true;
    else roots.emplace_back(a);
  }
  if (roots.empty()) {
    std::fprintf(stderr, "usage: scene_replay [--expect-rejected] PATH...\n");
    return 2;
  }
  int failures = 0;
  std::size_t total = 0;
  std::map<std::string, int> counts;
  for (const fs::path& root : roots) {
    const std::vector<fs::path> files = collect(root);
    if (files.empty()) {
      std::printf("FAIL %s: no files (missing path or empty directory)\n", root.string().c_str());
      ++failures;
      continue;
    }
    for (const fs::path& f : files) {
      std::ifstream in(f, std::ios::binary);
      const std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      ++total;
      try {
        const Outcome o = lockstep::fuzz::fuzz_one_scene(data);
        ++counts[lockstep::fuzz::outcome_name(o)];
        if (expect_rejected && o != Outcome::kRejected) {
          std::printf("FAIL %s: expected a SceneError, got '%s'\n", f.string().c_str(), lockstep::fuzz::outcome_name(o));
          ++failures;
        } else {
          std::printf("ok   %s: %s\n", f.string().c_str(), lockstep::fuzz::outcome_name(o));
        }
      } catch (const std::exception& e) {
        std::printf("FAIL %s: %s\n", f.string().c_str(), e.what());
        ++failures;
      }
    }
  }
  std::printf("%zu files:", total);
  for (const auto& [name, n] : counts) std::printf(" %d %s", n, name.c_str());
  std::printf("; %d failure%s\n", failures, failures == 1 ? "" : "s");
  return failures == 0 ? 0 : 1;
}
