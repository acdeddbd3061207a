// The scenes compiled into the server: server/live/scene_library.h.
#include "server/live/scene_library.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "sim/io/scene_json.h"
#include "sim/scene/scene_validation.h"
#include "sim/surgery/scene_file.h"
#include "sim/surgery/scene_presets.h"

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
  EXPECT_EQ(scene.solver.dt, 2.5e-4);
  const auto block = sim::surgery::make_block_surgery(scene);  // its selections pick nodes
  EXPECT_EQ(block.spec.tissue.num_nodes(), 13 * 13 * 5);
  EXPECT_EQ(std::count(block.spec.fixed.begin(), block.spec.fixed.end(), 1), 13 * 13);
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

TEST(SceneVersion, IsTheRuntimeAndTheFnv1a64OfTheTextInHex) {
  // The published FNV-1a 64 test vectors.
  EXPECT_EQ(text_hash(""), "cbf29ce484222325");
  EXPECT_EQ(text_hash("a"), "af63dc4c8601ec8c");
  EXPECT_EQ(text_hash("foobar"), "85944171f73967e8");
  EXPECT_EQ(scene_version("foobar"), "6:85944171f73967e8");
}

TEST(SceneVersion, ARecordingReplaysOnItsRuntimeAgainstItsSceneText) {
  const std::string block(find_scene("scenes/palpation.json")->text);
  const std::string liver(find_scene("scenes/surgery/liver_station.json")->text);
  const std::string block_id = "scenes/palpation.json";
  const std::string liver_id = "scenes/surgery/liver_station.json";
  EXPECT_EQ(replay_refusal(block_id, scene_version(block), block), "");
  EXPECT_EQ(replay_refusal(liver_id, scene_version(liver), liver), "");
  // Runtime 1 (a bare hash) ran the block on the retired sim core simulation; runtimes 1 and 2
  // rounded the corotational forces differently, runtime 3 made a probe inside the tissue, and
  // runtime 4 left tissue inside out, runtime 5 held a tip pulled back along its shaft and cut
  // through tangles: none replays bit for bit here.
  EXPECT_EQ(replay_refusal(block_id, text_hash(block), block),
            "it was recorded on simulation runtime 1 (the palpation block's retired sim core "
            "simulation), and this server replays runtime 6; its scores stand");
  EXPECT_EQ(replay_refusal(liver_id, text_hash(liver), liver),
            "it was recorded on simulation runtime 1, and this server replays runtime 6; its "
            "scores stand");
  EXPECT_EQ(replay_refusal(liver_id, "2:" + text_hash(liver), liver),
            "it was recorded on simulation runtime 2, and this server replays runtime 6; its "
            "scores stand");
  EXPECT_EQ(replay_refusal(liver_id, "3:" + text_hash(liver), liver),
            "it was recorded on simulation runtime 3, and this server replays runtime 6; its "
            "scores stand");
  EXPECT_EQ(replay_refusal(liver_id, "4:" + text_hash(liver), liver),
            "it was recorded on simulation runtime 4, and this server replays runtime 6; its "
            "scores stand");
  EXPECT_EQ(replay_refusal(liver_id, "5:" + text_hash(liver), liver),
            "it was recorded on simulation runtime 5, and this server replays runtime 6; its "
            "scores stand");
  EXPECT_EQ(replay_refusal(block_id, "7:" + text_hash(block), block),
            "it was recorded on simulation runtime 7, and this server replays runtime 6; its "
            "scores stand");
  // A changed scene refuses.
  EXPECT_EQ(replay_refusal(liver_id, scene_version(liver), liver + " "),
            "it was made with scene version " + text_hash(liver) + "; the scene is now " +
                text_hash(liver + " ") + ", so it cannot be replayed exactly");
  EXPECT_NE(replay_refusal(block_id, scene_version(block), block + " "), "");
  EXPECT_NE(replay_refusal(block_id, "", block), "");
}

TEST(SceneVersion, IsStableAndChangesWithAnyOneCharacter) {
  const std::string text(find_scene("scenes/palpation.json")->text);
  const auto version = scene_version(text);
  ASSERT_EQ(version.size(), 18u);
  EXPECT_EQ(version.substr(0, 2), "6:");
  EXPECT_EQ(version.find_first_not_of("0123456789abcdef", 2), std::string::npos);
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
