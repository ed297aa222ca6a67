// Replays files through the snapshot fuzz function (snapshot_fuzz_one.hpp)
// with the normal toolchain:
//   snapshot_replay PATH...          each file (directories: their files, sorted)
//   snapshot_replay --check-seeds DIR  DIR holds exactly the seeds snapshot_seeds() makes
//   snapshot_replay --make-seeds DIR   writes them (tests/fuzz/snapshot_corpus)
// Exits 1 on a finding or a stale seed, 2 on a usage error.
#include <algorithm>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "snapshot_fuzz_one.hpp"

namespace fs = std::filesystem;

namespace {

std::vector<std::uint8_t> read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::vector<std::uint8_t>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: snapshot_replay PATH... | --make-seeds DIR | --check-seeds DIR\n");
    return 2;
  }
  const std::string first = argv[1];
  if (first == "--make-seeds" || first == "--check-seeds") {
    if (argc != 3) return 2;
    const fs::path dir = argv[2];
    int stale = 0;
    for (const auto& [name, bytes] : lockstep::fuzz::snapshot_seeds()) {
      const fs::path p = dir / name;
      if (first == "--make-seeds") {
        fs::create_directories(dir);
        std::ofstream out(p, std::ios::binary);
        out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
      } else if (read_file(p) != bytes) {
        std::printf("%s: stale (the format or the engine changed: snapshot_replay --make-seeds %s)\n", p.c_str(), dir.c_str());
        ++stale;
      }
    }
    return stale == 0 ? 0 : 1;
  }
  std::vector<fs::path> files;
  for (int i = 1; i < argc; ++i) {
    const fs::path root = argv[i];
    if (fs::is_directory(root)) {
      for (const auto& e : fs::recursive_directory_iterator(root))
        if (e.is_regular_file()) files.push_back(e.path());
    } else {
      files.push_back(root);
    }
  }
  std::sort(files.begin(), files.end());
  int findings = 0;
  for (const fs::path& p : files) {
    const std::vector<std::uint8_t> bytes = read_file(p);
    try {
      const lockstep::fuzz::Outcome o = lockstep::fuzz::fuzz_one_snapshot(bytes.data(), bytes.size());
      std::printf("%s: %s\n", p.c_str(), lockstep::fuzz::outcome_name(o));
    } catch (const std::exception& e) {
      std::printf("%s: FINDING: %s\n", p.c_str(), e.what());
      ++findings;
    }
  }
  std::printf("%zu files, %d findings\n", files.size(), findings);
  return findings == 0 ? 0 : 1;
}
