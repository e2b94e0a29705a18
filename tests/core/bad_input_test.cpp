// Bad input at library level: every case of tests/core/fixtures/bad/cases.txt
// (written by tests/core/make_bad_fixtures.py) makes load_scenario throw
// gather::Error whose message names the offending file and the problem.
// tests/cli/bad_input.sh checks the same cases through the command line.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "gather_core/error.hpp"
#include "gather_core/grid/map_loader.hpp"
#include "gather_core/input_file.hpp"
#include "gather_core/scenario/scenario.hpp"

namespace gather {
namespace {

const std::string kBad = std::string(GATHER_REPO_DIR) + "/tests/core/fixtures/bad/";

struct BadCase {
  std::string file;   // scenario in cases/
  std::string named;  // file name the message must contain
  std::string words;  // words naming the problem
};

std::vector<BadCase> bad_cases() {
  std::ifstream in(kBad + "cases.txt");
  std::vector<BadCase> out;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    BadCase c;
    s >> c.file >> c.named >> std::ws;
    std::getline(s, c.words);
    out.push_back(c);
  }
  return out;
}

TEST(BadInput, EveryCaseThrowsErrorNamingFileAndProblem) {
  const std::vector<BadCase> cases = bad_cases();
  ASSERT_GE(cases.size(), 35u) << "fixtures missing; run tests/core/make_bad_fixtures.py";
  for (const BadCase& c : cases) {
    SCOPED_TRACE(c.file);
    ASSERT_FALSE(c.words.empty());
    try {
      load_scenario(kBad + "cases/" + c.file);
      ADD_FAILURE() << "accepted";
    } catch (const Error& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(c.named), std::string::npos) << msg;
      EXPECT_NE(msg.find(c.words), std::string::npos) << msg;
      EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    } catch (const std::exception& e) {
      ADD_FAILURE() << "not a gather::Error: " << e.what();
    }
  }
}

// The cases that fail inside the map are also rejected by load_map directly.
TEST(BadInput, MapLoaderRejectsBrokenMaps) {
  const char* maps[] = {"missing_image.yaml",   "unknown_format.yaml",      "empty_image.yaml",
                        "truncated_p5.yaml",    "truncated_p2.yaml",        "truncated_png.yaml",
                        "pgm16.yaml",           "missing_key.yaml",         "unknown_key.yaml",
                        "resolution_zero.yaml", "resolution_negative.yaml", "thresholds_order.yaml",
                        "malformed.yaml",       "wrong_type.yaml",          "bad_mode.yaml",
                        "rotated.yaml",         "nonexistent.yaml"};
  for (const char* m : maps) {
    SCOPED_TRACE(m);
    EXPECT_THROW(load_map(kBad + "maps/" + m), Error);
  }
}

// The fixtures' valid map, and a scenario giving only the required keys
// (every optional section missing takes its defaults).
TEST(BadInput, TheValidFixtureMapAndAMinimalScenarioLoad) {
  const OccupancyGrid g = load_map(kBad + "maps/ok.yaml");
  EXPECT_EQ(g.width(), 10);
  EXPECT_EQ(g.height(), 8);
  EXPECT_TRUE(g.is_free(g.world_to_cell({1.25, 1.25})));
  EXPECT_FALSE(g.is_free(g.world_to_cell({2.75, 2.25})));

  const std::string path = ::testing::TempDir() + "gather_minimal.scenario.yaml";
  std::ofstream(path) << "map: " << kBad << "maps/ok.yaml\noc: [1.25, 1.25]\n";
  const Scenario s = load_scenario(path);
  EXPECT_EQ(s.team.agents, TeamParams{}.agents);
  EXPECT_DOUBLE_EQ(s.radio.exponent, RadioParams{}.exponent);
  EXPECT_EQ(s.mission.cycles, MissionParams{}.cycles);
  EXPECT_EQ(s.planner.methods.size(), 3u);
  std::remove(path.c_str());
}

TEST(BadInput, UserTextInAnErrorIsOneShortLine) {
  EXPECT_EQ(quote_input("plain"), "plain");
  EXPECT_EQ(quote_input("a\nb\tc\rd\x01"
                        "e\x7f"),
            "a\\nb\\tc\\rd\\x01e\\x7f");
  EXPECT_EQ(quote_input(std::string(1000, 'x'), 10), std::string(10, 'x') + "...");
  EXPECT_EQ(quote_input(std::string(5, '\n'), 4), "\\n\\n...");  // escapes count
  EXPECT_LE(quote_input(std::string(1000, '\x01')).size(), 80u + 4 + 3);
}

// A YAML file small on disk but huge once built is refused while it is
// parsed (kMaxYamlNodes), before yaml-cpp builds a node: a flow list of a
// million numbers (6 MB, under the 16 MiB cap) took over 1 GB. At the cap
// itself a list still loads.
TEST(BadInput, AYamlFileOfTooManyValuesIsRefusedBeforeItIsBuilt) {
  const std::string path = ::testing::TempDir() + "gather_many_values.scenario.yaml";
  auto write = [&](std::uint64_t values) {
    std::ofstream out(path);
    out << "map: " << kBad << "maps/ok.yaml\noc: [1.25, 1.25]\nplanner:\n  methods: [";
    for (std::uint64_t i = 0; i < values; ++i) out << (i ? ",1" : "1");
    out << "]\n";
  };
  write(1000000);
  try {
    load_scenario(path);
    ADD_FAILURE() << "accepted";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(path), std::string::npos) << msg;
    EXPECT_NE(msg.find("more than " + std::to_string(kMaxYamlNodes) + " YAML values"), std::string::npos) << msg;
  }
  // Just under the cap (the mapping, its keys and values count too): the
  // file parses, and is refused for what its list holds.
  write(kMaxYamlNodes - 20);
  try {
    load_scenario(path);
    ADD_FAILURE() << "accepted";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).find("YAML values"), std::string::npos) << e.what();
  }
  std::remove(path.c_str());
}

}  // namespace
}  // namespace gather
