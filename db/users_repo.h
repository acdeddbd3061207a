#pragma once
// Users and their roles.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "db/database.h"

namespace incise::db {

enum class Role { trainee, instructor, admin };
std::string_view to_string(Role role);
std::optional<Role> parse_role(std::string_view text);

struct User {
  std::int64_t id = 0;
  std::string username;
  std::string display_name;
  Role role = Role::trainee;
  std::int64_t created_at = 0;              // Unix seconds
  std::optional<std::int64_t> disabled_at;  // set: cannot log in (UsersRepo::set_disabled)
  bool must_change_password = false;        // set by an admin's reset, cleared by the user's change
};

struct NewUser {
  std::string username;
  std::string display_name;
  Role role = Role::trainee;
  std::string password;  // plain text; only its argon2id hash is stored
};

// A password's stored form (hash_password's argon2id string), made before the database is touched:
// hashing takes about 50 ms, and a caller that holds a lock or a transaction meanwhile stalls
// everyone else's requests.
struct PasswordHash {
  std::string value;
};

class UsersRepo {
 public:
  explicit UsersRepo(Database& db) : db_(db) {}

  // Throws Conflict when the username is taken. Hashes user.password here; a request handler
  // hashes first, outside its lock, and passes the hash (user.password is then unused).
  User create(const NewUser& user, std::int64_t now);
  User create(const NewUser& user, const PasswordHash& hash, std::int64_t now);
  std::optional<User> find(std::int64_t id);
  std::optional<User> find_by_username(std::string_view username);
  // The user when the password matches; takes about as long for an unknown username, so the
  // response time does not reveal which usernames exist.
  std::optional<User> authenticate(std::string_view username, std::string_view password);
  // The user and their stored hash, for a caller that verifies the password without holding the
  // database (verify_password or, for nullopt, spend_password_check: the same time either way).
  struct Credentials {
    User user;
    std::string password_hash;
  };
  std::optional<Credentials> credentials(std::string_view username);
  std::string password_hash(std::int64_t id);  // "" for an unknown id
  std::vector<User> list();
  std::int64_t count();

  // Disables (at = the moment) or re-enables (nullopt) the user. Disabling also ends every login
  // session of theirs. Throws NotFound for an unknown id.
  void set_disabled(std::int64_t id, std::optional<std::int64_t> at);
  // Replaces the password (hashed). must_change: the user must choose another before anything
  // else (an admin's reset); the reset also ends every login session of theirs. Throws NotFound.
  // The first hashes here; a request handler hashes first, outside its lock.
  void set_password(std::int64_t id, std::string_view password, bool must_change);
  void set_password(std::int64_t id, const PasswordHash& hash, bool must_change);
  // Whether `password` is the user's present one (for a change that proves the old password).
  bool password_matches(std::int64_t id, std::string_view password);

  // Instructor assignments (trainee_instructors): an instructor sees the records of the trainees
  // assigned to them. set_instructors replaces a trainee's set; callers run it in a transaction
  // with what goes with it.
  void set_instructors(std::int64_t trainee_id, const std::vector<std::int64_t>& instructor_ids,
                       std::int64_t now);
  std::vector<std::int64_t> instructors_of(std::int64_t trainee_id);
  bool teaches(std::int64_t instructor_id, std::int64_t trainee_id);

 private:
  Database& db_;
};

}  // namespace incise::db
