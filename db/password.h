#pragma once
// Password hashing with libsodium's argon2id (memory-hard). The stored string
// carries its own salt and parameters.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace incise::db {

std::string hash_password(std::string_view password);
// What is wrong with a new password for `username` ("" when it is acceptable; docs/security.md):
// 10 to 256 characters (code points of its UTF-8, not bytes), no control characters, not the
// username, not one character repeated, not one of the most common passwords.
std::string password_problem(std::string_view password, std::string_view username);
// Constant-time check; false for a malformed hash.
bool verify_password(std::string_view password, const std::string& stored_hash);
// Spends the work of a verification and fails: for an unknown username, so that the response
// time does not reveal which usernames exist.
void spend_password_check(std::string_view password);

// A random token for cookies and station keys: 32 random bytes as 64 hex characters.
std::string random_token();
// SHA-256 of a token, for storage (only hashes of tokens are kept in the database).
std::vector<std::uint8_t> token_hash(std::string_view token);

}  // namespace incise::db
