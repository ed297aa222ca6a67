// The text form of the vector files: deterministic, diff-friendly JSON. A
// value whose one-line form fits in kInlineWidth is written on one line (one
// test, one body state); a longer array of numbers or strings is wrapped
// several values per line within kLineWidth; anything else is written one
// member per line. Keys keep their order.
#pragma once
#include <string>

#include "lockstep/vectors/common.hpp"

namespace lockstep::vectors {

inline constexpr std::size_t kInlineWidth = 220;
inline constexpr std::size_t kLineWidth = 120;

std::string to_text(const Json& value);

// Reads a whole file as JSON; throws FormatError naming the file.
Json read_json_file(const std::string& path);
// Writes to_text(value) + "\n"; throws std::runtime_error naming the file.
void write_json_file(const std::string& path, const Json& value);

}  // namespace lockstep::vectors
