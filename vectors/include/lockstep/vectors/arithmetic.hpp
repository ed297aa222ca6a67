// Level 1 vectors: every Q16.16 operation (fixed/include/lockstep/fixed/q16.hpp,
// q16_vec.hpp) with its inputs, raw output and the status flags it raises,
// including the rounding and overflow edges. File: arithmetic.json.
#pragma once
#include <string>
#include <vector>

#include "lockstep/vectors/common.hpp"

namespace lockstep::vectors {

// The operations in file order ("add", "mul", ..., "rotate").
std::vector<std::string> arithmetic_operations();

// The whole arithmetic.json document.
Json generate_arithmetic();

// The outputs of operation `op` on inputs `in`: {"out": {"r": ...}, "status": [...]}.
// Throws FormatError (naming `path`) for an unknown op or malformed inputs.
Json compute_arithmetic(const std::string& op, const Json& in, const std::string& path);

// Recomputes every test of an arithmetic.json document; the first test whose
// output or status differs is named by tcId, operation and field.
Verdict verify_arithmetic(const Json& doc, const std::string& file_name);

}  // namespace lockstep::vectors
