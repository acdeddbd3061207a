#pragma once
// A real site's first login. A new database has no users, and only an admin can create them
// (POST /api/users); --demo creates some, but also accepts the demo stations' public tokens. So
// the server takes the first admin's password from its environment, INCISE_ADMIN_PASSWORD (in
// Kubernetes, from a Secret), creates `admin` with it on a database without users, and makes them
// choose another password at the first login. With users present it changes nothing, so the
// variable may stay set.
#include <cstdint>
#include <string>
#include <string_view>

#include "db/database.h"

namespace incise::server {

struct FirstAdmin {
  bool created = false;
  std::string problem;  // why the password was refused ("" when fine); nothing was created
};

FirstAdmin create_first_admin(db::Database& db, std::string_view password, std::int64_t now);

}  // namespace incise::server
