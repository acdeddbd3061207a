#pragma once
// Accepts TCP connections and hands each to an HttpSession (Beast chat-multi's `listener`), over
// TLS when given a context.
#include <boost/asio.hpp>
#include <boost/asio/ssl/context.hpp>
#include <memory>

#include "server/app_state.h"

namespace incise::server {

class Listener : public std::enable_shared_from_this<Listener> {
 public:
  // Throws boost::system::system_error when the address cannot be bound.
  // `tls`: the server's TLS context (every connection is HTTPS), or null (plain HTTP).
  Listener(boost::asio::io_context& ioc, const boost::asio::ip::tcp::endpoint& endpoint,
           std::shared_ptr<AppState> app, std::shared_ptr<boost::asio::ssl::context> tls = nullptr);
  void run();
  void stop();
  unsigned short port() const;

 private:
  void do_accept();
  void on_accept(boost::system::error_code ec, boost::asio::ip::tcp::socket socket);

  boost::asio::io_context& ioc_;
  boost::asio::ip::tcp::acceptor acceptor_;
  std::shared_ptr<AppState> app_;
  std::shared_ptr<boost::asio::ssl::context> tls_;
};

}  // namespace incise::server
