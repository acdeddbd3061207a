#include "db/users_repo.h"

#include "db/password.h"
#include "db/statement.h"
#include "db/transaction.h"

namespace incise::db {

std::string_view to_string(Role role) {
  switch (role) {
    case Role::trainee:
      return "trainee";
    case Role::instructor:
      return "instructor";
    case Role::admin:
      return "admin";
  }
  return "trainee";
}

std::optional<Role> parse_role(std::string_view text) {
  if (text == "trainee") return Role::trainee;
  if (text == "instructor") return Role::instructor;
  if (text == "admin") return Role::admin;
  return std::nullopt;
}

namespace {
constexpr const char* kColumns =
    "id, username, display_name, role, created_at, disabled_at, must_change_password";

User read_user(const Statement& q) {
  return User{q.int64(0),     q.text(1),
              q.text(2),      parse_role(q.text(3)).value_or(Role::trainee),
              q.int64(4),     q.optional_int64(5),
              q.int64(6) != 0};
}
}  // namespace

User UsersRepo::create(const NewUser& user, std::int64_t now) {
  return create(user, PasswordHash{hash_password(user.password)}, now);
}

User UsersRepo::create(const NewUser& user, const PasswordHash& hash, std::int64_t now) {
  // ON CONFLICT DO NOTHING rather than catching the constraint error: on PostgreSQL a failed
  // statement would spoil the caller's transaction.
  auto q = db_.prepare(
      "INSERT INTO users (username, display_name, role, password_hash, created_at) VALUES (?, ?, "
      "?, ?, ?) ON CONFLICT (username) DO NOTHING RETURNING id");
  q.bind(1, user.username)
      .bind(2, user.display_name)
      .bind(3, to_string(user.role))
      .bind(4, hash.value)
      .bind(5, now);
  if (!q.step()) throw Conflict("username '" + user.username + "' is already taken");
  const std::int64_t id = q.int64(0);
  q.run();
  return User{id, user.username, user.display_name, user.role, now, {}, false};
}

std::optional<User> UsersRepo::find(std::int64_t id) {
  auto q = db_.prepare(std::string("SELECT ") + kColumns + " FROM users WHERE id = ?");
  q.bind(1, id);
  if (!q.step()) return std::nullopt;
  return read_user(q);
}

std::optional<User> UsersRepo::find_by_username(std::string_view username) {
  auto q = db_.prepare(std::string("SELECT ") + kColumns + " FROM users WHERE username = ?");
  q.bind(1, username);
  if (!q.step()) return std::nullopt;
  return read_user(q);
}

std::optional<User> UsersRepo::authenticate(std::string_view username, std::string_view password) {
  auto found = credentials(username);
  if (!found) {
    spend_password_check(password);
    return std::nullopt;
  }
  if (!verify_password(password, found->password_hash)) return std::nullopt;
  return std::move(found->user);
}

std::optional<UsersRepo::Credentials> UsersRepo::credentials(std::string_view username) {
  auto q = db_.prepare(std::string("SELECT ") + kColumns +
                       ", password_hash FROM users WHERE username = ?");
  q.bind(1, username);
  if (!q.step()) return std::nullopt;
  return Credentials{read_user(q), q.text(7)};
}

std::string UsersRepo::password_hash(std::int64_t id) {
  auto q = db_.prepare("SELECT password_hash FROM users WHERE id = ?");
  q.bind(1, id);
  return q.step() ? q.text(0) : std::string();
}

std::vector<User> UsersRepo::list() {
  auto q = db_.prepare(std::string("SELECT ") + kColumns + " FROM users ORDER BY username");
  std::vector<User> users;
  while (q.step())
    users.push_back(read_user(q));
  return users;
}

void UsersRepo::set_instructors(std::int64_t trainee_id,
                                const std::vector<std::int64_t>& instructor_ids, std::int64_t now) {
  db_.prepare("DELETE FROM trainee_instructors WHERE trainee_id = ?").bind(1, trainee_id).run();
  for (const auto instructor : instructor_ids) {
    db_.prepare(
           "INSERT INTO trainee_instructors (trainee_id, instructor_id, assigned_at) "
           "VALUES (?, ?, ?) ON CONFLICT DO NOTHING")
        .bind(1, trainee_id)
        .bind(2, instructor)
        .bind(3, now)
        .run();
  }
}

std::vector<std::int64_t> UsersRepo::instructors_of(std::int64_t trainee_id) {
  auto q = db_.prepare(
      "SELECT instructor_id FROM trainee_instructors WHERE trainee_id = ? ORDER BY instructor_id");
  q.bind(1, trainee_id);
  std::vector<std::int64_t> out;
  while (q.step())
    out.push_back(q.int64(0));
  return out;
}

bool UsersRepo::teaches(std::int64_t instructor_id, std::int64_t trainee_id) {
  auto q =
      db_.prepare("SELECT 1 FROM trainee_instructors WHERE instructor_id = ? AND trainee_id = ?");
  q.bind(1, instructor_id);
  q.bind(2, trainee_id);
  return q.step();
}

void UsersRepo::set_disabled(std::int64_t id, std::optional<std::int64_t> at) {
  Transaction tx(db_);
  db_.prepare("UPDATE users SET disabled_at = ? WHERE id = ?").bind(1, at).bind(2, id).run();
  if (db_.changes() == 0) throw NotFound("user " + std::to_string(id) + " does not exist");
  if (at) db_.prepare("DELETE FROM auth_sessions WHERE user_id = ?").bind(1, id).run();
  tx.commit();
}

void UsersRepo::set_password(std::int64_t id, std::string_view password, bool must_change) {
  set_password(id, PasswordHash{hash_password(password)}, must_change);
}

void UsersRepo::set_password(std::int64_t id, const PasswordHash& hash, bool must_change) {
  Transaction tx(db_);
  db_.prepare("UPDATE users SET password_hash = ?, must_change_password = ? WHERE id = ?")
      .bind(1, hash.value)
      .bind(2, must_change ? 1 : 0)
      .bind(3, id)
      .run();
  if (db_.changes() == 0) throw NotFound("user " + std::to_string(id) + " does not exist");
  if (must_change) db_.prepare("DELETE FROM auth_sessions WHERE user_id = ?").bind(1, id).run();
  tx.commit();
}

bool UsersRepo::password_matches(std::int64_t id, std::string_view password) {
  const auto hash = password_hash(id);
  return !hash.empty() && verify_password(password, hash);
}

std::int64_t UsersRepo::count() {
  auto q = db_.prepare("SELECT COUNT(*) FROM users");
  q.step();
  return q.int64(0);
}

}  // namespace incise::db
