#pragma once
// The TLS set-ups of the server and the agent (docs/security.md, "TLS"): TLS 1.2 or newer only,
// OpenSSL's default cipher list (forward-secret suites first), no compression, no renegotiation.
#include <boost/asio/ssl/context.hpp>
#include <memory>
#include <string>

namespace incise::transport {

// The server's context with its certificate chain and private key (PEM files). Throws
// std::runtime_error naming the file and OpenSSL's reason when one cannot be used (missing,
// unreadable, not PEM, a key that does not match the certificate).
std::shared_ptr<boost::asio::ssl::context> make_server_tls(const std::string& certificate_chain,
                                                           const std::string& private_key);

// A client's context that verifies the server: against `ca_file` (PEM; a private CA or the
// server's own self-signed certificate) or, when it is empty, the system's trusted CAs. The
// host name is checked per connection (verify_host_name). Throws std::runtime_error like the
// above.
std::shared_ptr<boost::asio::ssl::context> make_client_tls(const std::string& ca_file);

}  // namespace incise::transport
