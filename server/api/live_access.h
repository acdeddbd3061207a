#pragma once
// Who may see and control a session: its trainee, instructors and admins (docs/api.md).
#include "db/training_repo.h"
#include "db/users_repo.h"

namespace incise::server::api {

// Throws ApiError 403 unless user may see the session.
void check_session_access(const db::User& user, const db::SessionRecord& session);

}  // namespace incise::server::api
