// The dashboard's files from the real server.
#include <gtest/gtest.h>

#include <string>

#include "server_fixture.h"

namespace incise::server::test {
namespace {

using Dashboard = ServerTest;

TEST_F(Dashboard, IndexAndClientRoutes) {
  auto client = new_client();
  for (const char* path : {"/", "/trainee", "/login"}) {
    const auto response = client->get(path);
    EXPECT_EQ(response.status, 200) << path;
    EXPECT_EQ(response.body, kIndexHtml) << path;
    EXPECT_EQ(response.content_type, "text/html; charset=utf-8") << path;
  }
}

TEST_F(Dashboard, MissingFilesAre404) {
  EXPECT_TRUE(is_error(new_client()->get("/missing.js"), 404, "no such file: /missing.js"));
}

TEST_F(Dashboard, PathsOutsideTheWebRootAreRefused) {
  auto client = new_client();
  for (const char* path :
       {"/../../etc/passwd", "/assets/../../../etc/passwd", "/..%2f..%2fetc/passwd"}) {
    const auto response = client->get(path);
    EXPECT_TRUE(is_error(response, 400, "illegal request path")) << path;
  }
  // An absolute path after the first slash must stay inside the web root too (index.html, the
  // client-side route fallback, is a fine answer).
  for (const char* path : {"//etc/passwd", "///etc/passwd"}) {
    const auto response = client->get(path);
    EXPECT_EQ(response.body.find("root:"), std::string::npos) << path;
    if (response.status == 200) {
      EXPECT_EQ(response.body, kIndexHtml) << path;
    }
  }
}

}  // namespace
}  // namespace incise::server::test
