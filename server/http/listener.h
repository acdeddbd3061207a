#pragma once
// Accepts TCP connections and hands each to an HttpSession (Beast chat-multi's `listener`).
#include <boost/asio.hpp>
#include <memory>

#include "server/app_state.h"

namespace incise::server {

class Listener : public std::enable_shared_from_this<Listener> {
 public:
  // Throws boost::system::system_error when the address cannot be bound.
  Listener(boost::asio::io_context& ioc, const boost::asio::ip::tcp::endpoint& endpoint,
           std::shared_ptr<AppState> app);
  void run();
  void stop();
  unsigned short port() const;

 private:
  void do_accept();
  void on_accept(boost::system::error_code ec, boost::asio::ip::tcp::socket socket);

  boost::asio::io_context& ioc_;
  boost::asio::ip::tcp::acceptor acceptor_;
  std::shared_ptr<AppState> app_;
};

}  // namespace incise::server
