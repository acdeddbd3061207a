#pragma once
// The checks every test of a refused wire frame makes (devices/protocol.h): the decode failed,
// with the expected error, and a reason that is not empty, fits a WebSocket close frame and, when
// the test names one, is exactly that text.
#include <gtest/gtest.h>

#include <string_view>

#include "devices/protocol.h"

namespace incise::test {

template <typename Result>
void expect_decode_error(const Result& result, devices::DecodeErrc error,
                         std::string_view reason = {}) {
  EXPECT_FALSE(result.ok());
  EXPECT_EQ(result.error(), error) << result.reason();
  EXPECT_FALSE(result.reason().empty());
  EXPECT_LE(result.reason().size(), devices::kMaxCloseReasonSize);
  if (!reason.empty()) {
    EXPECT_EQ(result.reason(), reason);
  }
}

}  // namespace incise::test
