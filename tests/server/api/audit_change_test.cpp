// What the audit log keeps of a change: server/api/audit_change.h.
#include "server/api/audit_change.h"

#include <gtest/gtest.h>

namespace incise::server::api {
namespace {

using nlohmann::json;

TEST(ChangedFields, KeepsOnlyTheFieldsThatDiffer) {
  const auto changed = changed_fields({{"kind", "bench"}, {"retired", false}},
                                      {{"kind", "laparoscopy"}, {"retired", false}});
  EXPECT_EQ(changed.before, (json{{"kind", "bench"}}));
  EXPECT_EQ(changed.after, (json{{"kind", "laparoscopy"}}));
}

TEST(ChangedFields, EqualDocumentsChangeNothing) {
  const json doc = {{"a", 1}, {"b", {1, 2, 3}}};
  const auto changed = changed_fields(doc, doc);
  EXPECT_TRUE(changed.before.empty());
  EXPECT_TRUE(changed.after.empty());
}

TEST(ChangedFields, NamesANestedChangeByItsPath) {
  // A curriculum's threshold edit: only that number, at its place.
  json before = {{"name", "Basic"},
                 {"modules", {{{"tasks", {{{"key", "a"}, {"thresholds", {{{"max", 2.0}}}}}}}}}}};
  json after = before;
  after["modules"][0]["tasks"][0]["thresholds"][0]["max"] = 1.5;
  const auto changed = changed_fields(before, after);
  EXPECT_EQ(changed.before, (json{{"modules/0/tasks/0/thresholds/0/max", 2.0}}));
  EXPECT_EQ(changed.after, (json{{"modules/0/tasks/0/thresholds/0/max", 1.5}}));
}

TEST(ChangedFields, AddedAndRemovedFieldsAreNullOnTheOtherSide) {
  const json task_a = {{"key", "a"}};
  const json task_b = {{"key", "b"}};
  const auto changed = changed_fields({{"old", 1}, {"tasks", {task_a}}},
                                      {{"new", "x"}, {"tasks", {task_a, task_b}}});
  EXPECT_EQ(changed.before, (json{{"old", 1}, {"new", nullptr}, {"tasks/1", nullptr}}));
  EXPECT_EQ(changed.after, (json{{"old", nullptr}, {"new", "x"}, {"tasks/1", task_b}}));
}

TEST(ChangedFields, EveryAppendedElementKeepsItsOwnPlace) {
  // Two tasks added to a module: both are in the log, each at its index.
  const json t0 = {{"key", "a"}};
  const json t1 = {{"key", "b"}};
  const json t2 = {{"key", "c"}};
  const auto changed = changed_fields({{"tasks", {t0}}}, {{"tasks", {t0, t1, t2}}});
  EXPECT_EQ(changed.before, (json{{"tasks/1", nullptr}, {"tasks/2", nullptr}}));
  EXPECT_EQ(changed.after, (json{{"tasks/1", t1}, {"tasks/2", t2}}));
}

TEST(ChangedFields, AListOfPlainValuesChangesWhole) {
  // Who teaches a trainee: [2] -> [], [] -> [2, 3], [2, 3] -> [3].
  const auto ids = [](json list) { return json{{"instructor_ids", std::move(list)}}; };
  for (const auto& [from, to] :
       {std::pair{json{2}, json::array()}, std::pair{json::array(), json{2, 3}},
        std::pair{json{2, 3}, json{3}}}) {
    const auto changed = changed_fields(ids(from), ids(to));
    EXPECT_EQ(changed.before, ids(from)) << from << " -> " << to;
    EXPECT_EQ(changed.after, ids(to)) << from << " -> " << to;
  }
}

TEST(ChangedFields, ACreationKeepsItsWholeAfter) {
  const json created = {{"id", 3}, {"name", "Bench 5"}};
  const auto changed = changed_fields(nullptr, created);
  EXPECT_TRUE(changed.before.empty());
  EXPECT_EQ(changed.after, created);
}

TEST(ChangedFields, KeysWithSlashesReadAsThemselves) {
  const auto changed = changed_fields({{"a/b", 1}, {"c~d", 1}}, {{"a/b", 2}, {"c~d", 2}});
  EXPECT_EQ(changed.after, (json{{"a/b", 2}, {"c~d", 2}}));
}

}  // namespace
}  // namespace incise::server::api
