#include "server/first_admin.h"

#include "db/password.h"
#include "db/transaction.h"
#include "db/users_repo.h"

namespace incise::server {

FirstAdmin create_first_admin(db::Database& db, std::string_view password, std::int64_t now) {
  constexpr std::string_view kUsername = "admin";
  db::Transaction tx(db);  // two nodes starting together create one admin
  db::UsersRepo users(db);
  if (users.count() > 0) return {};
  if (auto problem = db::password_problem(password, kUsername); !problem.empty()) {
    return {false, "INCISE_ADMIN_PASSWORD: " + problem};
  }
  const auto admin = users.create(
      {std::string(kUsername), "Administrator", db::Role::admin, std::string(password)}, now);
  // The password passed through an environment and a deployment's files: replace it at once.
  users.set_password(admin.id, password, true);
  tx.commit();
  return {true, ""};
}

}  // namespace incise::server
