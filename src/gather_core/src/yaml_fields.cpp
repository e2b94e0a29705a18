#include "gather_core/yaml_fields.hpp"

#include <cstdint>
#include <sstream>

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/parser.h>

#include "gather_core/input_file.hpp"

namespace gather {
namespace yaml {

namespace {

// Counts the first document's nodes as the parser meets them, before any is
// built, and refuses aliases (kMaxYamlNodes).
class NodeBudget final : public YAML::EventHandler {
 public:
  explicit NodeBudget(const std::string& path) : path_(path) {}
  void OnDocumentStart(const YAML::Mark&) override {}
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark& m, YAML::anchor_t) override { count(m); }
  void OnAlias(const YAML::Mark& m, YAML::anchor_t) override {
    throw Error(path_, "line " + std::to_string(m.line + 1) + ": YAML aliases (*name) are not accepted");
  }
  void OnScalar(const YAML::Mark& m, const std::string&, YAML::anchor_t, const std::string&) override { count(m); }
  void OnSequenceStart(const YAML::Mark& m, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {
    count(m);
  }
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark& m, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {
    count(m);
  }
  void OnMapEnd() override {}

 private:
  void count(const YAML::Mark& m) {
    if (++nodes_ > kMaxYamlNodes)
      throw Error(path_, "more than " + std::to_string(kMaxYamlNodes) + " YAML values (at line " +
                             std::to_string(m.line + 1) +
                             "), more than any scenario, map or plan holds (docs/input_limits.md)");
  }
  const std::string& path_;
  std::uint64_t nodes_ = 0;
};

}  // namespace

YAML::Node load_file(const std::string& path) {
  const std::vector<uint8_t> bytes = read_input_file(path, kMaxYamlBytes, "YAML file");
  try {
    const std::string text(bytes.begin(), bytes.end());
    {
      std::istringstream in(text);
      YAML::Parser parser(in);
      NodeBudget budget(path);
      parser.HandleNextDocument(budget);
    }
    YAML::Node root = YAML::Load(text);
    if (!root.IsMap()) throw Error(path, "expected a YAML mapping at the top level");
    return root;
  } catch (const YAML::Exception& e) {
    throw Error(path, "YAML syntax error at line " + std::to_string(e.mark.line + 1) + ": " + quote_input(e.msg));
  }
}

std::string resolve_path(const std::string& file, const std::string& relative) {
  if (relative.empty() || relative[0] == '/') return relative;
  const auto slash = file.find_last_of('/');
  return slash == std::string::npos ? relative : file.substr(0, slash + 1) + relative;
}

std::string Fields::file_name(const std::string& key) const {
  std::string named = required<std::string>(key);
  if (named.empty()) throw Error(file_, "key '" + name(key) + "' is empty: it must name a file");
  return named;
}

Fields::Fields(const YAML::Node& node, std::string file, std::string prefix)
    : node_(node), file_(std::move(file)), prefix_(std::move(prefix)) {
  if (node_.IsDefined() && !node_.IsNull() && !node_.IsMap()) throw Error(file_, "'" + prefix_ + "' must be a mapping");
}

void Fields::allow(std::initializer_list<const char*> keys) const {
  if (!node_.IsMap()) return;
  for (const auto& kv : node_) {
    // A non-scalar key ("[a, b]: 1") must not escape as a yaml-cpp exception without the file name.
    const std::string key = kv.first.IsScalar() ? kv.first.Scalar() : "<non-scalar key>";
    bool known = false;
    for (const char* k : keys) known = known || key == k;
    if (!known) {
      std::string list;
      for (const char* k : keys) list += (list.empty() ? "" : ", ") + std::string(k);
      throw Error(file_, "unknown key '" + quote_input(name(key), 60) + "' (line " +
                             std::to_string(kv.first.Mark().line + 1) + "; known: " + list + ")");
    }
  }
}

Fields Fields::section(const std::string& key) const {
  // An absent key gives a zombie node on which IsMap() throws InvalidNode; use an empty node.
  const YAML::Node child = node_.IsMap() ? node_[key] : YAML::Node();
  return Fields(child.IsDefined() ? child : YAML::Node(), file_, name(key));
}

}  // namespace yaml
}  // namespace gather
