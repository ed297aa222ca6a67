// The harness's output: a summary table for the terminal and a report folder
// (CSV data and SVG pictures; docs/COMPARE.md lists every file and column).
#pragma once
#include <string>
#include <vector>

#include "lockstep/compare/harness.hpp"

namespace lockstep::compare {

// The terminal summary: one row per engine, then every failed check (at most
// max_failures, then a count), then the verdict line.
std::string summary_table(const Recording& recording, const Verdict& verdict, int max_failures = 20);

// Writes the report folder (created if missing) and returns the paths written.
// Throws std::runtime_error when a file cannot be written.
std::vector<std::string> write_report(const std::string& dir, const Recording& recording, const Verdict& verdict);

// Writes text to a file, creating its parent folders; throws std::runtime_error naming the path.
void write_file(const std::string& path, const std::string& text);

}  // namespace lockstep::compare
