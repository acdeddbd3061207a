#include "server/http/static_files.h"

#include <fstream>
#include <sstream>

#include "server/api/router.h"

namespace incise::server {

namespace {
std::string_view mime_type(const std::filesystem::path& path) {
  const auto ext = path.extension().string();
  if (ext == ".html") return "text/html; charset=utf-8";
  if (ext == ".js" || ext == ".mjs") return "text/javascript; charset=utf-8";
  if (ext == ".css") return "text/css; charset=utf-8";
  if (ext == ".json") return "application/json";
  if (ext == ".svg") return "image/svg+xml";
  if (ext == ".png") return "image/png";
  if (ext == ".jpg" || ext == ".jpeg") return "image/jpeg";
  if (ext == ".ico") return "image/x-icon";
  if (ext == ".woff2") return "font/woff2";
  if (ext == ".map") return "application/json";
  return "application/octet-stream";
}

bool read_file(const std::filesystem::path& path, std::string& out) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::ostringstream buffer;
  buffer << in.rdbuf();
  out = std::move(buffer).str();
  return true;
}
}  // namespace

Response serve_static(const Request& request, const std::filesystem::path& web_root) {
  const auto version = request.version();
  const bool keep_alive = request.keep_alive();
  if (request.method() != http::verb::get && request.method() != http::verb::head) {
    return json_error(http::status::method_not_allowed, "only GET and HEAD are served here",
                      version, keep_alive);
  }
  const auto target = request.target();
  std::string path(target.substr(0, target.find('?')));
  if (path.find("..") != std::string::npos || path.find('\0') != std::string::npos ||
      path.empty() || path[0] != '/') {
    return json_error(http::status::bad_request, "illegal request path", version, keep_alive);
  }
  // "//x" would make `web_root / "/x"` the absolute path "/x": refuse it with the other tricks.
  if (path.find("//") != std::string::npos) {
    return json_error(http::status::bad_request, "illegal request path", version, keep_alive);
  }
  const std::filesystem::path relative(path.substr(1));
  if (relative.is_absolute()) {
    return json_error(http::status::bad_request, "illegal request path", version, keep_alive);
  }
  std::filesystem::path file = web_root / relative;
  std::error_code ec;
  const bool is_asset = std::filesystem::is_regular_file(file, ec);
  if (!is_asset) {
    // Missing files with an extension are real 404s; everything else is a client-side route.
    if (std::filesystem::path(path).has_extension()) {
      return json_error(http::status::not_found, "no such file: " + path, version, keep_alive);
    }
    file = web_root / "index.html";
  }
  std::string body;
  if (!read_file(file, body)) {
    return json_error(http::status::not_found,
                      "the dashboard is not built (no " + file.string() + "); run deploy/build.sh",
                      version, keep_alive);
  }
  Response res{http::status::ok, version};
  res.set(http::field::content_type, mime_type(file));
  // Vite fingerprints assets, so they may be cached for long; index.html must always be fresh.
  res.set(http::field::cache_control,
          path.rfind("/assets/", 0) == 0 ? "public, max-age=31536000, immutable" : "no-cache");
  res.set("X-Content-Type-Options", "nosniff");
  res.keep_alive(keep_alive);
  if (request.method() == http::verb::head) {
    res.content_length(body.size());
  } else {
    res.body() = std::move(body);
    res.prepare_payload();
  }
  return res;
}

}  // namespace incise::server
