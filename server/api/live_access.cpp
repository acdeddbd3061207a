#include "server/api/live_access.h"

#include "server/api/api_error.h"

namespace incise::server::api {

void check_session_access(const db::User& user, const db::SessionRecord& session) {
  if (user.role == db::Role::trainee && session.trainee_id != user.id) {
    throw ApiError(boost::beast::http::status::forbidden,
                   "session " + std::to_string(session.id) + " belongs to another trainee");
  }
}

}  // namespace incise::server::api
