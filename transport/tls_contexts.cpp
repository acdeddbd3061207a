#include "transport/tls_contexts.h"

#include <stdexcept>

namespace incise::transport {

namespace ssl = boost::asio::ssl;

namespace {
std::shared_ptr<ssl::context> modern_context(ssl::context::method method) {
  auto context = std::make_shared<ssl::context>(method);
  context->set_options(ssl::context::default_workarounds | ssl::context::no_sslv2 |
                       ssl::context::no_sslv3 | ssl::context::no_tlsv1 | ssl::context::no_tlsv1_1 |
                       ssl::context::no_compression);
  SSL_CTX_set_options(context->native_handle(), SSL_OP_NO_RENEGOTIATION);
  // A key with a passphrase fails to load (with OpenSSL's reason) instead of prompting on a
  // terminal a service does not have.
  context->set_password_callback(
      [](std::size_t, ssl::context::password_purpose) { return std::string(); });
  return context;
}

// What OpenSSL said, with what we were doing.
[[noreturn]] void fail(const std::string& what, const std::string& file,
                       const boost::system::system_error& e) {
  throw std::runtime_error(what + " " + file + ": " + e.code().message());
}
}  // namespace

std::shared_ptr<ssl::context> make_server_tls(const std::string& certificate_chain,
                                              const std::string& private_key) {
  auto context = modern_context(ssl::context::tls_server);
  try {
    context->use_certificate_chain_file(certificate_chain);
  } catch (const boost::system::system_error& e) {
    fail("cannot use the TLS certificate", certificate_chain, e);
  }
  try {
    // OpenSSL refuses a key that does not match the certificate loaded above.
    context->use_private_key_file(private_key, ssl::context::pem);
  } catch (const boost::system::system_error& e) {
    fail("cannot use the TLS private key", private_key, e);
  }
  return context;
}

std::shared_ptr<ssl::context> make_client_tls(const std::string& ca_file) {
  auto context = modern_context(ssl::context::tls_client);
  context->set_verify_mode(ssl::verify_peer);
  try {
    if (ca_file.empty()) {
      context->set_default_verify_paths();
    } else {
      context->load_verify_file(ca_file);
    }
  } catch (const boost::system::system_error& e) {
    fail("cannot use the CA file", ca_file.empty() ? "(system default)" : ca_file, e);
  }
  return context;
}

}  // namespace incise::transport
