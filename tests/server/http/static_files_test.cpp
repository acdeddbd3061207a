// The dashboard's files: server/http/static_files.h.
#include "server/http/static_files.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/support/temp_dir.h"

namespace incise::server {
namespace {

const std::string kIndex = "<!doctype html><title>Incise</title>";
const std::string kScript = "console.log('incise');";
const std::string kSecret = "not for the web";

void write_file(const std::filesystem::path& path, const std::string& text) {
  std::filesystem::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << text;
}

// <tmp>/web is the web root; <tmp>/secret.txt lies outside it.
class StaticFiles : public ::testing::Test {
 protected:
  StaticFiles() : root_(dir_.path() / "web"), secret_(dir_.path() / "secret.txt") {
    write_file(root_ / "index.html", kIndex);
    write_file(root_ / "assets" / "app-1234.js", kScript);
    write_file(secret_, kSecret);
  }

  Response get(const std::string& target, http::verb method = http::verb::get) const {
    Request request{method, target, 11};
    request.set(http::field::host, "incise.test");
    return serve_static(request, root_);
  }

  static std::string error_of(const Response& response) {
    const auto body = nlohmann::json::parse(response.body(), nullptr, false);
    return body.is_object() && body.contains("error") && body["error"].is_string()
               ? body["error"].get<std::string>()
               : "(no JSON error in '" + response.body() + "')";
  }

  test::TempDir dir_{"incise-static"};
  std::filesystem::path root_;
  std::filesystem::path secret_;
};

TEST_F(StaticFiles, ClientRoutesServeIndexHtml) {
  for (const char* target : {"/", "/trainee", "/login", "/admin/users", "/?next=%2Fscores"}) {
    const auto response = get(target);
    EXPECT_EQ(response.result(), http::status::ok) << target;
    EXPECT_EQ(response.body(), kIndex) << target;
    EXPECT_EQ(response[http::field::content_type], "text/html; charset=utf-8") << target;
    EXPECT_EQ(response[http::field::cache_control], "no-cache") << target;
  }
}

TEST_F(StaticFiles, AssetsAreServedWithTheirTypeAndLongCaching) {
  const auto response = get("/assets/app-1234.js");
  EXPECT_EQ(response.result(), http::status::ok);
  EXPECT_EQ(response.body(), kScript);
  EXPECT_EQ(response[http::field::content_type], "text/javascript; charset=utf-8");
  EXPECT_EQ(response[http::field::cache_control], "public, max-age=31536000, immutable");
  EXPECT_EQ(response["X-Content-Type-Options"], "nosniff");
}

TEST_F(StaticFiles, HeadGivesTheLengthWithoutTheBody) {
  const auto response = get("/", http::verb::head);
  EXPECT_EQ(response.result(), http::status::ok);
  EXPECT_EQ(response.body(), "");
  EXPECT_EQ(response[http::field::content_length], std::to_string(kIndex.size()));
}

TEST_F(StaticFiles, MissingFilesWithAnExtensionAre404) {
  const auto response = get("/missing.js");
  EXPECT_EQ(response.result(), http::status::not_found);
  EXPECT_EQ(error_of(response), "no such file: /missing.js");
}

TEST_F(StaticFiles, OnlyGetAndHead) {
  const auto response = get("/", http::verb::post);
  EXPECT_EQ(response.result(), http::status::method_not_allowed);
  EXPECT_EQ(error_of(response), "only GET and HEAD are served here");
}

TEST_F(StaticFiles, DotDotPathsAreRefused) {
  for (const char* target : {"/../secret.txt", "/../../etc/passwd", "/assets/../../secret.txt",
                             "/..", "/a/..%2f..%2fsecret.txt"}) {
    const auto response = get(target);
    EXPECT_EQ(response.result(), http::status::bad_request) << target;
    EXPECT_EQ(error_of(response), "illegal request path") << target;
  }
}

// "//x" would make web_root / "/x" == "/x": an absolute path must never leave the web root. (A
// path with no file behind it is a client-side route, so index.html is a fine answer.)
TEST_F(StaticFiles, AbsolutePathsDoNotLeaveTheWebRoot) {
  for (const std::string& target :
       {"/" + secret_.string(), std::string("//etc/passwd"), std::string("///etc/passwd")}) {
    const auto response = get(target);
    EXPECT_EQ(response.body().find(kSecret), std::string::npos) << target;
    EXPECT_EQ(response.body().find("root:"), std::string::npos) << target;
    if (response.result() == http::status::ok) {
      EXPECT_EQ(response.body(), kIndex) << target;
    }
  }
}

TEST_F(StaticFiles, NoDashboardBuilt) {
  std::filesystem::remove(root_ / "index.html");
  const auto response = get("/trainee");
  EXPECT_EQ(response.result(), http::status::not_found);
  EXPECT_NE(error_of(response).find("the dashboard is not built"), std::string::npos);
}

}  // namespace
}  // namespace incise::server
