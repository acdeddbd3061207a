#pragma once
// Debian's nginx as the load balancer in front of server nodes, with the configuration that
// deploy/run-cluster.sh uses (deploy/cluster/nginx.conf.in): for the cluster test and
// bench_cluster.
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "server_fixture.h"

namespace incise::server::test {

// A free TCP port on loopback (the kernel's pick; free again when this returns).
inline unsigned short free_port() {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t size = sizeof address;
  bind(fd, reinterpret_cast<sockaddr*>(&address), size);
  getsockname(fd, reinterpret_cast<sockaddr*>(&address), &size);
  close(fd);
  return ntohs(address.sin_port);
}

// Debian's nginx with deploy/cluster/nginx.conf.in in front of `nodes`.
class Nginx {
 public:
  explicit Nginx(const std::vector<unsigned short>& nodes) : port_(free_port()) {
    std::ifstream in(std::string(INCISE_SOURCE_DIR) + "/deploy/cluster/nginx.conf.in");
    std::stringstream text;
    text << in.rdbuf();
    std::string conf = text.str();
    std::string upstreams;
    for (const auto port : nodes)
      upstreams +=
          "    server 127.0.0.1:" + std::to_string(port) + " max_fails=1 fail_timeout=30s;\n";
    const auto fill = [&](const std::string& field, const std::string& value) {
      for (auto at = conf.find(field); at != std::string::npos; at = conf.find(field, at))
        conf.replace(at, field.size(), value);
    };
    fill("@PREFIX@", dir_.path().string());
    fill("@PORT@", std::to_string(port_));
    fill("@UPSTREAMS@", upstreams);
    // As root, nginx's workers would run as nobody, who may not write under the test's directory.
    fill("@USER@", geteuid() == 0 ? "user root;" : "");
    std::ofstream(dir_.path() / "nginx.conf") << conf;
    process_ = std::make_unique<ChildProcess>(std::vector<std::string>{
        "/usr/sbin/nginx", "-p", dir_.path().string(), "-c", (dir_.path() / "nginx.conf").string(),
        "-e", (dir_.path() / "error.log").string()});
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (std::chrono::steady_clock::now() < deadline &&
           HttpClient("127.0.0.1", port_).get("/api/health").status != 200)
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ~Nginx() {
    // QUIT would wait for the live WebSockets; a test's balancer just goes.
    process_->send_signal(SIGTERM);
    process_->wait_for_exit(std::chrono::seconds(5));
  }
  unsigned short port() const { return port_; }
  std::string log() const {
    std::ifstream in(dir_.path() / "error.log");
    std::stringstream text;
    text << in.rdbuf();
    return text.str() + process_->stderr_text();
  }

 private:
  TempDir dir_{"incise-nginx"};
  unsigned short port_;
  std::unique_ptr<ChildProcess> process_;
};

}  // namespace incise::server::test
