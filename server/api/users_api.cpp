#include <algorithm>
#include <string>
#include <vector>

#include "db/transaction.h"
#include "server/api/api_error.h"
#include "server/api/audit_change.h"
#include "server/api/handlers.h"
#include "server/api/json_views.h"
#include "server/api/request_fields.h"

namespace incise::server::api {

namespace {
void check_username(const std::string& name) {
  const bool ok =
      name.size() >= 3 && name.size() <= 32 && std::all_of(name.begin(), name.end(), [](char c) {
        return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '.' || c == '_' || c == '-';
      });
  if (!ok) {
    throw ApiError(http::status::unprocessable_entity,
                   "username must be 3-32 characters of a-z, 0-9, '.', '_' or '-'");
  }
}
// The instructor ids of a request body: distinct ids of users whose role is instructor.
std::vector<std::int64_t> instructor_ids(db::Database& db, const nlohmann::json& value) {
  const auto fail = [](const std::string& why) {
    throw ApiError(http::status::unprocessable_entity, "instructor_ids " + why);
  };
  if (!value.is_array()) fail("must be an array of user ids");
  std::vector<std::int64_t> ids;
  db::UsersRepo users(db);
  for (const auto& v : value) {
    if (!v.is_number_integer()) fail("must hold user ids (integers)");
    const auto id = v.get<std::int64_t>();
    const auto user = users.find(id);
    if (!user || user->role != db::Role::instructor) {
      fail("must name instructors; user " + std::to_string(id) + " is not one");
    }
    if (std::find(ids.begin(), ids.end(), id) != ids.end()) {
      fail("names user " + std::to_string(id) + " twice");
    }
    ids.push_back(id);
  }
  return ids;
}

nlohmann::json user_json(db::UsersRepo& users, const db::User& user) {
  auto out = to_json(user);
  if (user.role == db::Role::trainee) out["instructor_ids"] = users.instructors_of(user.id);
  return out;
}

std::string id_list(const std::vector<std::int64_t>& ids) {
  std::string text;
  for (const auto id : ids)
    text += (text.empty() ? "" : ", ") + std::to_string(id);
  return "[" + text + "]";
}

}  // namespace

ApiResponse list_users(ApiContext& ctx) {
  ctx.require_role({db::Role::admin});
  db::UsersRepo users(ctx.db());
  auto out = nlohmann::json::array();
  for (const auto& u : users.list())
    out.push_back(user_json(users, u));
  return {http::status::ok, out, {}};
}

ApiResponse set_trainee_instructors(ApiContext& ctx) {
  const auto& admin = ctx.require_role({db::Role::admin});
  auto& db = ctx.db();
  db::UsersRepo users(db);
  const auto trainee = users.find(ctx.path_id);
  if (!trainee) {
    throw ApiError(http::status::not_found,
                   "user " + std::to_string(ctx.path_id) + " does not exist");
  }
  if (trainee->role != db::Role::trainee) {
    throw ApiError(http::status::unprocessable_entity,
                   trainee->username + " is not a trainee; only trainees have instructors");
  }
  const auto body = ctx.json_body();
  const RequestFields fields(body, {"instructor_ids"});
  const auto ids = instructor_ids(db, fields.required("instructor_ids"));
  db::Transaction tx(db);  // "before" and the change, with no other writer between them
  const nlohmann::json before = {{"instructor_ids", users.instructors_of(trainee->id)}};
  users.set_instructors(trainee->id, ids, ctx.now);
  audit_change(db, admin.id, "user.instructors", trainee->username + " taught by " + id_list(ids),
               ctx.now, before, {{"instructor_ids", ids}});
  tx.commit();
  return {http::status::ok, user_json(users, *trainee), {}};
}

ApiResponse create_user(ApiContext& ctx) {
  const auto& admin = ctx.require_role({db::Role::admin});
  const auto body = ctx.json_body();
  const RequestFields fields(body,
                             {"username", "password", "role", "display_name", "instructor_ids"});
  db::NewUser user;
  user.username = fields.string("username");
  check_username(user.username);
  user.display_name = fields.text_or("display_name", user.username);
  if (user.display_name.empty() || user.display_name.size() > 80) {
    throw ApiError(http::status::unprocessable_entity, "display_name must be 1-80 characters");
  }
  const auto role_text = fields.string("role");
  const auto role = db::parse_role(role_text);
  if (!role) {
    throw ApiError(http::status::unprocessable_entity,
                   "role must be trainee, instructor or admin (got '" + role_text + "')");
  }
  user.role = *role;
  user.password = fields.string("password");
  check_new_password("password", user.password, user.username);
  if (body.contains("instructor_ids") && user.role != db::Role::trainee) {
    throw ApiError(http::status::unprocessable_entity, "only trainees have instructor_ids");
  }
  // Hashed before the transaction; the admin is checked again inside it.
  const db::PasswordHash hash = ctx.hash_password(user.password);
  std::vector<std::int64_t> instructors;
  if (body.contains("instructor_ids")) {
    instructors = instructor_ids(ctx.db(), body["instructor_ids"]);
  }
  db::UsersRepo users(ctx.db());
  db::Transaction tx(ctx.db());
  ctx.reread_user();
  ctx.require_role({db::Role::admin});
  const auto created = users.create(user, hash, ctx.now);
  if (!instructors.empty()) users.set_instructors(created.id, instructors, ctx.now);
  audit_change(ctx.db(), admin.id, "user.create",
               created.username + " (" + std::string(db::to_string(created.role)) + ")" +
                   (instructors.empty() ? "" : " taught by " + id_list(instructors)),
               ctx.now, nullptr, user_json(users, created));
  tx.commit();
  return {http::status::created, user_json(users, created), {}};
}

namespace {
db::User existing_user(db::UsersRepo& users, std::int64_t id) {
  auto user = users.find(id);
  if (!user)
    throw ApiError(http::status::not_found, "user " + std::to_string(id) + " does not exist");
  return *user;
}
}  // namespace

ApiResponse update_user(ApiContext& ctx) {
  const auto& admin = ctx.require_role({db::Role::admin});
  const auto body = ctx.json_body();
  const RequestFields fields(body, {"disabled"});
  const bool disabled = fields.boolean("disabled");
  auto& db = ctx.db();
  db::UsersRepo users(db);
  // The checks and the change with no other writer between them: two admins disabling each other
  // at once must not both succeed (the second finds its own login ended by the first).
  db::Transaction tx(db);
  ctx.reread_user();
  ctx.require_role({db::Role::admin});
  const auto before = existing_user(users, ctx.path_id);
  if (before.id == admin.id && disabled) {
    // Nobody would be left to undo it if this were the last admin.
    throw ApiError(http::status::conflict, "you cannot disable your own account");
  }
  const bool changes = before.disabled_at.has_value() != disabled;
  if (changes) {
    users.set_disabled(before.id, disabled ? std::optional<std::int64_t>(ctx.now) : std::nullopt);
    audit_change(db, admin.id, disabled ? "user.disable" : "user.enable", before.username, ctx.now,
                 {{"disabled", !disabled}}, {{"disabled", disabled}});
  }
  tx.commit();
  // Their logins ended with set_disabled; what they were watching ends too.
  if (changes && disabled) ctx.app.close_views_of(before.id, "your account was disabled");
  return {http::status::ok, user_json(users, existing_user(users, before.id)), {}};
}

ApiResponse reset_user_password(ApiContext& ctx) {
  const auto& admin = ctx.require_role({db::Role::admin});
  const auto body = ctx.json_body();
  const RequestFields fields(body, {"password"});
  const auto password = fields.string("password");
  auto& db = ctx.db();
  db::UsersRepo users(db);
  const auto named = existing_user(users, ctx.path_id);
  check_new_password("password", password, named.username);
  if (named.id == admin.id) {
    throw ApiError(http::status::conflict,
                   "reset only others' passwords; change your own with POST /api/me/password");
  }
  // Hashed before the transaction; the admin and the account are read again inside it (either may
  // have changed meanwhile).
  const db::PasswordHash hash = ctx.hash_password(password);
  db::Transaction tx(db);
  ctx.reread_user();
  ctx.require_role({db::Role::admin});
  const auto before = existing_user(users, named.id);
  users.set_password(before.id, hash, true);
  audit_change(db, admin.id, "user.password_reset", before.username, ctx.now,
               {{"must_change_password", before.must_change_password}},
               {{"must_change_password", true}});
  tx.commit();
  ctx.app.close_views_of(before.id, "an admin reset your password; log in again");
  return {http::status::ok, user_json(users, existing_user(users, before.id)), {}};
}

}  // namespace incise::server::api
