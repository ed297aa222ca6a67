#include "lockstep/vectors/json_text.hpp"

#include <fstream>
#include <sstream>

namespace lockstep::vectors {
namespace {

// One-line form with ", " and ": " separators.
void inline_form(const Json& v, std::string& out) {
  if (v.is_object()) {
    out += '{';
    bool first = true;
    for (auto it = v.begin(); it != v.end(); ++it) {
      if (!first) out += ", ";
      first = false;
      out += Json(it.key()).dump();
      out += ": ";
      inline_form(it.value(), out);
    }
    out += '}';
  } else if (v.is_array()) {
    out += '[';
    for (std::size_t i = 0; i < v.size(); ++i) {
      if (i) out += ", ";
      inline_form(v[i], out);
    }
    out += ']';
  } else {
    out += v.dump();
  }
}

bool all_scalars(const Json& v) {
  for (const Json& e : v)
    if (e.is_structured()) return false;
  return true;
}

// lead: characters already on the line before the value (indent, key).
void block_form(const Json& v, std::size_t indent, std::size_t lead, std::string& out) {
  std::string one;
  inline_form(v, one);
  if (!v.is_structured() || v.empty() || lead + one.size() + 1 <= kInlineWidth) {
    out += one;
    return;
  }
  const std::string pad(indent + 2, ' ');
  if (v.is_array() && all_scalars(v)) {
    out += "[\n" + pad;
    std::size_t col = pad.size();
    for (std::size_t i = 0; i < v.size(); ++i) {
      std::string e = v[i].dump();
      if (i + 1 < v.size()) e += ",";
      if (col > pad.size() && col + 1 + e.size() > kLineWidth) {
        out += "\n" + pad;
        col = pad.size();
      } else if (col > pad.size()) {
        out += ' ';
        ++col;
      }
      out += e;
      col += e.size();
    }
    out += "\n" + std::string(indent, ' ') + "]";
    return;
  }
  out += v.is_array() ? "[\n" : "{\n";
  std::size_t i = 0;
  for (auto it = v.begin(); it != v.end(); ++it, ++i) {
    std::string key = v.is_object() ? Json(it.key()).dump() + ": " : std::string();
    out += pad + key;
    block_form(it.value(), indent + 2, pad.size() + key.size(), out);
    if (i + 1 < v.size()) out += ',';
    out += '\n';
  }
  out += std::string(indent, ' ') + (v.is_array() ? "]" : "}");
}

}  // namespace

std::string to_text(const Json& value) {
  std::string out;
  block_form(value, 0, 0, out);
  return out;
}

Json read_json_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FormatError(path + ": cannot read the file");
  std::stringstream ss;
  ss << in.rdbuf();
  try {
    return Json::parse(ss.str());
  } catch (const nlohmann::json::exception& e) {
    throw FormatError(path + ": not valid JSON: " + e.what());
  }
}

void write_json_file(const std::string& path, const Json& value) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw std::runtime_error(path + ": cannot write the file");
  out << to_text(value) << "\n";
  if (!out) throw std::runtime_error(path + ": write failed");
}

}  // namespace lockstep::vectors
