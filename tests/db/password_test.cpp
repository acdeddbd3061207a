// Tests for db/password.h. Each argon2id hash costs about 0.1 s, so the hashes are shared.
#include "db/password.h"

#include <gtest/gtest.h>

#include <cctype>
#include <cstdint>
#include <string>
#include <vector>

namespace incise::db {
namespace {

std::string to_hex(const std::vector<std::uint8_t>& bytes) {
  static const char digits[] = "0123456789abcdef";
  std::string out;
  for (const auto b : bytes) {
    out += digits[b >> 4];
    out += digits[b & 0xf];
  }
  return out;
}

class PasswordTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    first_ = hash_password("correct horse");
    second_ = hash_password("correct horse");
  }

  inline static std::string first_;
  inline static std::string second_;
};

TEST_F(PasswordTest, HashVerifies) {
  EXPECT_TRUE(verify_password("correct horse", first_));
  EXPECT_TRUE(verify_password("correct horse", second_));
}

TEST_F(PasswordTest, WrongPasswordFails) {
  EXPECT_FALSE(verify_password("correct hors", first_));
  EXPECT_FALSE(verify_password("correct horse ", first_));
  EXPECT_FALSE(verify_password("Correct horse", first_));
  EXPECT_FALSE(verify_password("", first_));
}

TEST_F(PasswordTest, SamePasswordHashesDifferentlyBecauseOfTheSalt) {
  EXPECT_NE(first_, second_);
}

TEST_F(PasswordTest, HashIsArgon2idAndDoesNotContainThePassword) {
  EXPECT_EQ(first_.rfind("$argon2id$", 0), 0u) << first_;
  EXPECT_EQ(first_.find("correct horse"), std::string::npos);
}

TEST_F(PasswordTest, MalformedStoredHashReturnsFalse) {
  EXPECT_FALSE(verify_password("correct horse", ""));
  EXPECT_FALSE(verify_password("correct horse", "correct horse"));
  EXPECT_FALSE(verify_password("correct horse", "$argon2id$v=19$garbage"));
  // A valid hash with its digest cut short.
  EXPECT_FALSE(verify_password("correct horse", first_.substr(0, first_.size() - 4)));
}

TEST(Password, PasswordWithEmbeddedNulIsHashedWhole) {
  // Truncating at the NUL would let "a" log in for "a\0b".
  const std::string password = std::string("a") + '\0' + "b";
  const std::string hash = hash_password(password);
  EXPECT_TRUE(verify_password(password, hash));
  EXPECT_FALSE(verify_password("a", hash));
}

TEST(RandomToken, Is64LowercaseHexCharacters) {
  const std::string token = random_token();
  ASSERT_EQ(token.size(), 64u);
  for (const char c : token)
    EXPECT_TRUE(std::isxdigit(static_cast<unsigned char>(c)) && !std::isupper(c)) << token;
}

TEST(RandomToken, Differs) {
  EXPECT_NE(random_token(), random_token());
}

TEST(TokenHash, IsSha256) {
  // FIPS 180-2 test vectors.
  EXPECT_EQ(to_hex(token_hash("abc")),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(to_hex(token_hash("")),
            "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(to_hex(token_hash("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq")),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
}

TEST(TokenHash, DependsOnEveryByte) {
  const std::string token = random_token();
  std::string changed = token;
  changed.back() = changed.back() == '0' ? '1' : '0';
  EXPECT_NE(token_hash(token), token_hash(changed));
  EXPECT_EQ(token_hash(token), token_hash(token));
}

}  // namespace
}  // namespace incise::db

namespace incise::db {
namespace {

// The policy for a new password (docs/security.md): each rule with a password that just fails it
// and one that just passes.
TEST(PasswordPolicy, CountsCharactersNotBytes) {
  const std::string four_emoji = "\xF0\x9F\x98\x80\xF0\x9F\x98\x80\xF0\x9F\x98\x80\xF0\x9F\x98\x80";
  ASSERT_EQ(four_emoji.size(), 16u);  // 16 bytes, 4 characters
  EXPECT_EQ(password_problem(four_emoji, "dana"), "must have at least 10 characters");
  EXPECT_EQ(password_problem("kestrel-09", "dana"), "");  // 10
  EXPECT_EQ(password_problem("kestrel-0", "dana"), "must have at least 10 characters");
  EXPECT_EQ(password_problem("fl\xC3\xBCgelhorn-1", "dana"), "");  // ü is one character
  EXPECT_EQ(password_problem(std::string(256, 'x') + "y", "dana"),
            "must have at most 256 characters");
}

TEST(PasswordPolicy, RefusesControlCharacters) {
  EXPECT_EQ(password_problem(std::string("kestrel\0-0942", 13), "dana"),
            "must not contain control characters");
  EXPECT_EQ(password_problem("kestrel\t-0942", "dana"), "must not contain control characters");
  EXPECT_EQ(password_problem("kestrel\x7F-0942", "dana"), "must not contain control characters");
  EXPECT_EQ(password_problem("kestrel\xC2\x85-0942", "dana"),  // U+0085, a C1 control
            "must not contain control characters");
  EXPECT_EQ(password_problem("kestrel\xC2\xA0-0942", "dana"), "");  // U+00A0 is a character
}

TEST(PasswordPolicy, RefusesTheUsernameRepeatsAndCommonPasswords) {
  EXPECT_EQ(password_problem("Dana.Smith-1", "dana.smith-1"), "must not be the username");
  EXPECT_EQ(password_problem("aaaaaaaaaa", "dana"), "must not be one character repeated");
  EXPECT_EQ(password_problem("          ", "dana"), "must not be one character repeated");
  std::string euros;
  for (int i = 0; i < 10; ++i)
    euros += "\xE2\x82\xAC";  // U+20AC, three bytes
  EXPECT_EQ(password_problem(euros, "dana"), "must not be one character repeated");
  EXPECT_EQ(password_problem(euros + "x", "dana"), "");
  for (const char* common : {"password12", "PassWord12", "1234567890", "qwertyuiop"}) {
    EXPECT_EQ(password_problem(common, "dana"),
              "is one of the most common passwords; choose another")
        << common;
  }
  EXPECT_EQ(password_problem("password12!", "dana"), "");
}

}  // namespace
}  // namespace incise::db
