#include "lockstep/vectors/vectors.hpp"

#include <algorithm>
#include <filesystem>

#include "lockstep/builtin_scenes.hpp"
#include "lockstep/vectors/arithmetic.hpp"
#include "lockstep/vectors/formulas.hpp"
#include "lockstep/vectors/json_text.hpp"

namespace lockstep::vectors {

namespace fs = std::filesystem;

std::vector<std::string> generate_directory(const std::string& dir, const GenerateOptions& options, std::ostream* log) {
  fs::create_directories(fs::path(dir) / "scenes");
  std::vector<std::string> written;
  Json files = Json::array();
  auto put = [&](const std::string& rel, const Json& doc) {
    write_json_file((fs::path(dir) / rel).string(), doc);
    written.push_back(rel);
    files.push_back(Json{{"path", rel}, {"level", doc["level"]}, {"numberOfTests", doc["numberOfTests"]}});
    if (log)
      *log << "wrote " << (fs::path(dir) / rel).string() << " (" << doc["numberOfTests"].get<long>() << " tests)\n";
  };
  put("arithmetic.json", generate_arithmetic());
  put("formulas.json", generate_formulas());
  const std::vector<std::string> names = options.scenes.empty() ? builtin_scene_names() : options.scenes;
  for (const std::string& name : names) {
    const auto scene = builtin_scene(name);
    if (!scene) throw std::invalid_argument("unknown built-in scene '" + name + "'");
    put("scenes/" + name + ".json", generate_scene_vectors(*scene, options.scene));
  }
  Json index;
  index["algorithm"] = "lockstep test vectors";
  index["schema"] = "lockstep_index_schema_v1.json";
  index["schemaVersion"] = kSchemaVersion;
  index["generatorVersion"] = generator_version();
  index["regenerate"] = kRegenerateCommand;
  index["files"] = std::move(files);
  write_json_file((fs::path(dir) / "index.json").string(), index);
  written.push_back("index.json");
  if (log) *log << "wrote " << (fs::path(dir) / "index.json").string() << "\n";
  return written;
}

std::string source_dir() { return LOCKSTEP_SOURCE_DIR; }

std::vector<Verdict> verify_directory(const std::string& dir, const VerifyOptions& options, std::ostream* log) {
  std::vector<Verdict> out;
  Json index;
  try {
    index = read_json_file((fs::path(dir) / "index.json").string());
    if (int_at(index, "schemaVersion", "index.json") != kSchemaVersion)
      throw FormatError("index.json: schemaVersion " + index["schemaVersion"].dump() + " is not supported");
    if (!member(index, "files", "index.json").is_array()) throw FormatError("index.json: files must be an array");
  } catch (const FormatError& e) {
    Verdict v;
    v.ok = false;
    v.file = "index.json";
    v.message = e.what();
    out.push_back(v);
    return out;
  }
  std::vector<std::string> scene_files;
  for (const Json& f : index["files"]) {
    const std::string rel = f.value("path", "");
    const long level = f.value("level", 0L);
    if (level == 3) scene_files.push_back(rel);
    const bool wanted =
        (level == 1 && options.arithmetic) || (level == 2 && options.formulas) || (level == 3 && options.scenes);
    if (!wanted) continue;
    const std::string scene_name = level == 3 ? fs::path(rel).stem().string() : "";
    if (level == 3 && !options.only_scenes.empty() &&
        std::find(options.only_scenes.begin(), options.only_scenes.end(), scene_name) == options.only_scenes.end())
      continue;
    Verdict v;
    try {
      const Json doc = read_json_file((fs::path(dir) / rel).string());
      if (level == 1) {
        v = verify_arithmetic(doc, rel);
      } else if (level == 2) {
        v = verify_formulas(doc, rel);
      } else {
        SceneVerifyOptions so;
        const auto it = options.max_frames.find(scene_name);
        if (it != options.max_frames.end()) so.max_frames = it->second;
        v = verify_scene_vectors(doc, rel, so);
      }
    } catch (const FormatError& e) {
      v.ok = false;
      v.file = rel;
      v.message = e.what();
    }
    if (log) {
      if (v.ok)
        *log << "ok   " << rel << " (" << v.checked << (level == 3 ? " frames" : " tests") << ")\n";
      else
        *log << "FAIL " << v.message << "\n";
    }
    out.push_back(v);
  }
  if (options.scenes && options.only_scenes.empty()) {
    for (const std::string& name : builtin_scene_names()) {
      const std::string rel = "scenes/" + name + ".json";
      if (std::find(scene_files.begin(), scene_files.end(), rel) != scene_files.end()) continue;
      Verdict v;
      v.ok = false;
      v.file = rel;
      v.message =
          rel + ": missing: built-in scene '" + name + "' has no vector file (regenerate: " + kRegenerateCommand + ")";
      if (log) *log << "FAIL " << v.message << "\n";
      out.push_back(v);
    }
  }
  return out;
}

}  // namespace lockstep::vectors
