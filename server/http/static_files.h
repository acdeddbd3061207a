#pragma once
// Serves the built dashboard. Client-side routes (/login, /trainee, ...) fall back to index.html;
// paths that try to leave the web root are refused.
#include <filesystem>

#include "server/api/api_context.h"

namespace incise::server {

Response serve_static(const Request& request, const std::filesystem::path& web_root);

}  // namespace incise::server
