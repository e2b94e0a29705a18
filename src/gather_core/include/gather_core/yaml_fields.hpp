#pragma once
// Strict YAML reading: every key is known, every value has the right type, and
// every error names the file and the key ("maps/x.yaml: team.agents: ...").
#include <yaml-cpp/yaml.h>

#include <initializer_list>
#include <string>
#include <vector>

#include "gather_core/error.hpp"

namespace gather {
namespace yaml {

// Loads a YAML file; throws Error(path, ...) if it is missing or malformed.
YAML::Node load_file(const std::string& path);

// `relative` resolved against the directory of `file` (absolute paths unchanged).
std::string resolve_path(const std::string& file, const std::string& relative);

// The keys of one YAML mapping.
class Fields {
 public:
  // `prefix` is the dotted path of the mapping ("" for the document root).
  Fields(const YAML::Node& node, std::string file, std::string prefix);

  // Throws if the mapping has a key not in `keys`.
  void allow(std::initializer_list<const char*> keys) const;
  bool has(const std::string& key) const { return node_[key].IsDefined() && !node_[key].IsNull(); }

  template <typename T>
  T required(const std::string& key) const {
    if (!has(key)) throw Error(file_, "missing key '" + name(key) + "'");
    return as<T>(key);
  }
  template <typename T>
  T optional(const std::string& key, const T& fallback) const {
    return has(key) ? as<T>(key) : fallback;
  }
  // A file the key names (a string, not empty), as written. Throws naming
  // the key.
  std::string file_name(const std::string& key) const;
  // The same, resolved against the directory of this YAML file (resolve_path).
  std::string file_path(const std::string& key) const { return resolve_path(file_, file_name(key)); }
  // A nested mapping; an absent key gives an empty mapping (all defaults).
  Fields section(const std::string& key) const;

  std::string name(const std::string& key) const { return prefix_.empty() ? key : prefix_ + "." + key; }
  const std::string& file() const { return file_; }

 private:
  template <typename T>
  T as(const std::string& key) const {
    try {
      return node_[key].as<T>();
    } catch (const YAML::Exception&) {
      throw Error(file_, "key '" + name(key) + "' has a value of the wrong type (line " +
                             std::to_string(node_[key].Mark().line + 1) + ")");
    }
  }
  YAML::Node node_;
  std::string file_;
  std::string prefix_;
};

}  // namespace yaml
}  // namespace gather
