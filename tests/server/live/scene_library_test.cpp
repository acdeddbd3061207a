// The scenes compiled into the server: server/live/scene_library.h.
#include "server/live/scene_library.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "sim/io/scene_json.h"
#include "sim/scene/scene_validation.h"
#include "sim/scene/simulation.h"
#include "sim/surgery/scene_file.h"

namespace incise::server::live {
namespace {

// The source tree's sim/scenes/, found from this file's path (tests/server/live/).
std::string read_source_scene(const std::string& name) {
  const auto path = std::filesystem::path(__FILE__).parent_path() / "../../../sim/scenes" / name;
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path.string());
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(SceneLibrary, PalpationSceneIsEmbeddedVerbatimAndValid) {
  const auto source = find_scene("scenes/palpation.json");
  ASSERT_TRUE(source.has_value());
  EXPECT_EQ(source->id, "scenes/palpation.json");
  EXPECT_EQ(source->text, read_source_scene("palpation.json"));

  const auto scene = sim::parse_scene_text(source->text);
  EXPECT_NO_THROW(sim::validate_scene(scene));
  ASSERT_TRUE(scene.tool.has_value());  // a live scene needs a probe and a camera
  EXPECT_EQ(scene.tool->radius, 0.005);
  ASSERT_TRUE(scene.view.has_value());
  EXPECT_EQ(scene.solver.dt, 1e-4);
  const sim::Simulation simulation(scene);  // its selections pick nodes of the mesh
  EXPECT_EQ(simulation.mesh().num_nodes(), 13 * 13 * 5);
}

TEST(SceneLibrary, EverySceneOfTheSourceTreeIsEmbedded) {
  const auto dir = std::filesystem::path(__FILE__).parent_path() / "../../../sim/scenes";
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".json") continue;
    const auto name = entry.path().filename().string();
    const auto source = find_scene("scenes/" + name);
    ASSERT_TRUE(source.has_value()) << name;
    EXPECT_EQ(source->text, read_source_scene(name)) << name;
    EXPECT_NO_THROW(sim::parse_scene_text(source->text)) << name;
    ++count;
  }
  EXPECT_GE(count, 2);  // palpation.json and clamped_box.json at least
}

TEST(SceneLibrary, EverySurgicalSceneIsEmbeddedUnderScenesSurgery) {
  const auto dir = std::filesystem::path(__FILE__).parent_path() / "../../../sim/scenes/surgery";
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    if (entry.path().extension() != ".json") continue;
    const auto name = "surgery/" + entry.path().filename().string();
    const auto source = find_scene("scenes/" + name);
    ASSERT_TRUE(source.has_value()) << name;
    EXPECT_EQ(source->text, read_source_scene(name)) << name;
    // Read and validated (not meshed: that is the surgery tests' and a session's).
    EXPECT_NO_THROW(sim::surgery::parse_surgical_scene_file(nlohmann::json::parse(source->text)))
        << name;
    ++count;
  }
  EXPECT_GE(count, 3);  // liver_surgery, knee_surgery and liver_station at least
  // The scripts folder holds tool scripts, not scenes.
  EXPECT_FALSE(find_scene("scenes/surgery/scripts/liver_cut.json").has_value());
}

TEST(SceneLibrary, UnknownIdsAreNotFound) {
  EXPECT_FALSE(find_scene("scenes/nothing.json").has_value());
  EXPECT_FALSE(find_scene("").has_value());
  EXPECT_FALSE(find_scene("palpation.json").has_value());  // the id includes the folder
  EXPECT_FALSE(find_scene("scenes/palpation.json ").has_value());
  EXPECT_FALSE(find_scene("scenes/Palpation.json").has_value());
  EXPECT_FALSE(find_scene("scenes/palpation").has_value());
}

TEST(SceneVersion, IsFnv1a64InHex) {
  // The published FNV-1a 64 test vectors.
  EXPECT_EQ(scene_version(""), "cbf29ce484222325");
  EXPECT_EQ(scene_version("a"), "af63dc4c8601ec8c");
  EXPECT_EQ(scene_version("foobar"), "85944171f73967e8");
}

TEST(SceneVersion, IsStableAndChangesWithAnyOneCharacter) {
  const std::string text(find_scene("scenes/palpation.json")->text);
  const auto version = scene_version(text);
  ASSERT_EQ(version.size(), 16u);
  EXPECT_EQ(version.find_first_not_of("0123456789abcdef"), std::string::npos);
  EXPECT_EQ(scene_version(std::string(text)), version);  // depends on the text only

  for (std::size_t at = 0; at < text.size(); ++at) {
    std::string changed = text;
    changed[at] = changed[at] == '1' ? '2' : '1';
    ASSERT_NE(scene_version(changed), version) << "character " << at;
  }
  EXPECT_NE(scene_version(text + " "), version);
  EXPECT_NE(scene_version(text.substr(0, text.size() - 1)), version);
}

}  // namespace
}  // namespace incise::server::live
