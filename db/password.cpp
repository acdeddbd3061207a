#include "db/password.h"

#include <sodium.h>

#include <stdexcept>

namespace incise::db {

namespace {
// The most common passwords of 10 or more characters in public breach corpora, lower case. A
// password equal to one of them, ignoring case, is refused.
constexpr std::string_view kCommonPasswords[] = {
    "0123456789",  "1234567890",  "0987654321",   "9876543210",  "12345678910",   "123456789a",
    "a123456789",  "1234567890a", "123456789q",   "1q2w3e4r5t",  "1qaz2wsx3edc",  "qwertyuiop",
    "qwerty1234",  "qwerty12345", "qwerty123456", "asdfghjkl1",  "asdfghjkl;",    "zxcvbnm123",
    "abcdefghij",  "abcd123456",  "abc1234567",   "password12",  "password123",   "password1234",
    "password01",  "passw0rd12",  "p@ssw0rd12",   "iloveyou12",  "iloveyou123",   "letmein123",
    "welcome123",  "welcome1234", "changeme12",   "changeme123", "administrator", "admin12345",
    "admin123456", "trustno1234", "football12",   "baseball12",  "sunshine12",    "princess12",
    "monkey1234",  "dragon1234",  "master1234",   "superman12",  "starwars12",    "computer12",
    "michael123",  "jessica123",
};

std::string lower_ascii(std::string_view text) {
  std::string out(text);
  for (auto& c : out)
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  return out;
}
}  // namespace

std::string password_problem(std::string_view password, std::string_view username) {
  // Characters, not bytes: a continuation byte (10xxxxxx) does not start one. The JSON reader has
  // refused invalid UTF-8 before this.
  std::size_t characters = 0;
  for (std::size_t i = 0; i < password.size(); ++i) {
    const auto byte = static_cast<unsigned char>(password[i]);
    if ((byte & 0xC0) != 0x80) ++characters;
    // C0 controls, DEL, and C1 controls (U+0080-U+009F, 0xC2 0x80-0x9F in UTF-8).
    const bool c1 = byte == 0xC2 && i + 1 < password.size() &&
                    static_cast<unsigned char>(password[i + 1]) >= 0x80 &&
                    static_cast<unsigned char>(password[i + 1]) <= 0x9F;
    if (byte < 0x20 || byte == 0x7F || c1) return "must not contain control characters";
  }
  if (characters < 10) return "must have at least 10 characters";
  if (characters > 256) return "must have at most 256 characters";
  const auto lower = lower_ascii(password);
  if (!username.empty() && lower == lower_ascii(username)) return "must not be the username";
  // One character repeated: the whole is copies of its first character's UTF-8 sequence.
  const auto lead = static_cast<unsigned char>(password.front());
  const std::size_t width = lead < 0x80 ? 1 : lead < 0xE0 ? 2 : lead < 0xF0 ? 3 : 4;
  const auto first = password.substr(0, width);
  bool repeated = password.size() % first.size() == 0;
  for (std::size_t i = 0; repeated && i < password.size(); i += first.size())
    repeated = password.substr(i, first.size()) == first;
  if (repeated) return "must not be one character repeated";
  for (const auto common : kCommonPasswords)
    if (lower == common) return "is one of the most common passwords; choose another";
  return "";
}

namespace {
void ensure_sodium() {
  static const int ok = sodium_init();
  if (ok < 0) throw std::runtime_error("libsodium failed to initialise");
}
}  // namespace

std::string hash_password(std::string_view password) {
  ensure_sodium();
  char out[crypto_pwhash_STRBYTES];
  // INTERACTIVE limits: about 64 MiB and well under a second, suited to a login request.
  if (crypto_pwhash_str(out, password.data(), password.size(), crypto_pwhash_OPSLIMIT_INTERACTIVE,
                        crypto_pwhash_MEMLIMIT_INTERACTIVE) != 0) {
    throw std::runtime_error("password hashing ran out of memory");
  }
  return out;
}

bool verify_password(std::string_view password, const std::string& stored_hash) {
  ensure_sodium();
  return crypto_pwhash_str_verify(stored_hash.c_str(), password.data(), password.size()) == 0;
}

void spend_password_check(std::string_view password) {
  static const std::string dummy = hash_password("incise-timing-equaliser");
  verify_password(password, dummy);
}

std::string random_token() {
  ensure_sodium();
  unsigned char bytes[32];
  randombytes_buf(bytes, sizeof bytes);
  char hex[sizeof bytes * 2 + 1];
  sodium_bin2hex(hex, sizeof hex, bytes, sizeof bytes);
  return hex;
}

std::vector<std::uint8_t> token_hash(std::string_view token) {
  ensure_sodium();
  std::vector<std::uint8_t> out(crypto_hash_sha256_BYTES);
  crypto_hash_sha256(out.data(), reinterpret_cast<const unsigned char*>(token.data()),
                     token.size());
  return out;
}

}  // namespace incise::db
