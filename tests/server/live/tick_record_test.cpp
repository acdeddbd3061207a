// The recording's per-tick records: server/live/tick_record.h.
#include "server/live/tick_record.h"

#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace incise::server::live {
namespace {

using Bytes = std::vector<std::uint8_t>;

// Every double that is not a NaN is a legal field value, including the extremes.
const double kExtremeDoubles[] = {0.0,
                                  -0.0,
                                  std::numeric_limits<double>::denorm_min(),
                                  -std::numeric_limits<double>::denorm_min(),
                                  std::numeric_limits<double>::min(),
                                  std::numeric_limits<double>::max(),
                                  std::numeric_limits<double>::lowest(),
                                  std::numeric_limits<double>::infinity(),
                                  -std::numeric_limits<double>::infinity(),
                                  std::numeric_limits<double>::epsilon()};
const float kExtremeFloats[] = {0.0f,
                                -0.0f,
                                std::numeric_limits<float>::denorm_min(),
                                std::numeric_limits<float>::min(),
                                std::numeric_limits<float>::max(),
                                std::numeric_limits<float>::lowest(),
                                std::numeric_limits<float>::infinity(),
                                -std::numeric_limits<float>::infinity()};

// A random non-NaN value: random bits, redrawn while they spell a NaN, so that every exponent
// and sign occurs; one draw in eight is an extreme value instead.
double any_double(std::mt19937_64& rng) {
  if (rng() % 8 == 0) return kExtremeDoubles[rng() % std::size(kExtremeDoubles)];
  double value;
  do {
    value = std::bit_cast<double>(rng());
  } while (std::isnan(value));
  return value;
}
float any_float(std::mt19937_64& rng) {
  if (rng() % 8 == 0) return kExtremeFloats[rng() % std::size(kExtremeFloats)];
  float value;
  do {
    value = std::bit_cast<float>(static_cast<std::uint32_t>(rng()));
  } while (std::isnan(value));
  return value;
}

// device_index is not part of the record (a tick records one device's input): it stays 0.
TickRecord any_record(std::mt19937_64& rng, std::uint32_t tick) {
  TickRecord r;
  r.tick = tick;
  r.shed = static_cast<std::uint8_t>(rng() % 4);
  r.input.buttons = static_cast<std::uint8_t>(rng());
  r.input.jaw = any_float(rng);
  r.input.position = {any_double(rng), any_double(rng), any_double(rng)};
  r.input.orientation = {any_double(rng), any_double(rng), any_double(rng), any_double(rng)};
  for (float& f : r.force)
    f = any_float(rng);
  return r;
}

template <class T>
bool same_bits(const T& a, const T& b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}

::testing::AssertionResult same_record(const TickRecord& a, const TickRecord& b) {
  const auto& s = a.input;
  const auto& t = b.input;
  const bool same =
      a.tick == b.tick && a.shed == b.shed && s.device_index == t.device_index &&
      s.buttons == t.buttons && same_bits(s.jaw, t.jaw) && same_bits(s.position.x, t.position.x) &&
      same_bits(s.position.y, t.position.y) && same_bits(s.position.z, t.position.z) &&
      same_bits(s.orientation.w, t.orientation.w) && same_bits(s.orientation.x, t.orientation.x) &&
      same_bits(s.orientation.y, t.orientation.y) && same_bits(s.orientation.z, t.orientation.z) &&
      same_bits(a.force[0], b.force[0]) && same_bits(a.force[1], b.force[1]) &&
      same_bits(a.force[2], b.force[2]);
  if (same) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << "records of tick " << a.tick << " / " << b.tick << " differ";
}

Bytes encode(const std::vector<TickRecord>& records) {
  Bytes out;
  for (const auto& r : records)
    append_tick_record(r, out);
  return out;
}

TEST(TickRecord, EachRecordIs77Bytes) {
  std::mt19937_64 rng(77);
  Bytes out;
  for (std::uint32_t i = 0; i < 10; ++i) {
    append_tick_record(any_record(rng, i), out);
    EXPECT_EQ(out.size(), (i + 1) * kTickRecordSize);
  }
  EXPECT_EQ(kTickRecordSize, 77u);
}

TEST(TickRecord, FieldsSitAtTheDocumentedOffsets) {
  TickRecord r;
  r.tick = 0x01020304;
  r.shed = 2;  // bits 29-30 of the tick field: 0x40 in its top byte
  r.input.buttons = 0xa5;
  r.input.jaw = 0.25f;
  r.input.position = {1.5, -2.5, 3.5};
  r.input.orientation = {0.5, -0.5, 0.25, -0.25};
  r.force[0] = 7.0f;
  r.force[1] = -8.0f;
  r.force[2] = 9.5f;
  Bytes out;
  append_tick_record(r, out);
  ASSERT_EQ(out.size(), kTickRecordSize);
  auto at = [&](std::size_t offset, auto value) {
    decltype(value) read;
    std::memcpy(&read, out.data() + offset, sizeof read);
    return same_bits(read, value);
  };
  EXPECT_EQ(out[0], 0x04);  // little-endian
  EXPECT_EQ(out[3], 0x41);
  EXPECT_EQ(out[4], 0xa5);
  EXPECT_TRUE(at(5, 0.25f));
  EXPECT_TRUE(at(9, 1.5));
  EXPECT_TRUE(at(17, -2.5));
  EXPECT_TRUE(at(25, 3.5));
  EXPECT_TRUE(at(33, 0.5));
  EXPECT_TRUE(at(41, -0.5));
  EXPECT_TRUE(at(49, 0.25));
  EXPECT_TRUE(at(57, -0.25));
  EXPECT_TRUE(at(65, 7.0f));
  EXPECT_TRUE(at(69, -8.0f));
  EXPECT_TRUE(at(73, 9.5f));
}

TEST(TickRecord, RandomRecordsRoundTripBitForBit) {
  std::mt19937_64 rng(20240611);
  std::vector<TickRecord> records;
  // Up to the last tick a recording can number (bits 29-30 carry the shedding level, bit 31
  // marks a second hand's record), each with some shedding level.
  const std::uint32_t first = kMaxRecordedTick - 4999;
  for (std::uint32_t i = 0; i < 5000; ++i)
    records.push_back(any_record(rng, first + i));
  const Bytes bytes = encode(records);
  ASSERT_EQ(bytes.size(), records.size() * kTickRecordSize);

  std::vector<TickRecord> decoded;
  ASSERT_EQ(decode_tick_records(bytes, decoded), "");
  ASSERT_EQ(decoded.size(), records.size());
  for (std::size_t i = 0; i < records.size(); ++i)
    ASSERT_TRUE(same_record(decoded[i], records[i])) << "record " << i;
  // Encoding the decoded records gives the same bytes.
  EXPECT_EQ(encode(decoded), bytes);
}

TEST(TickRecord, TwoHandedRecordsRoundTripAndAMisplacedSecondHandIsRejected) {
  std::mt19937_64 rng(7);
  std::vector<TickRecord> records;
  for (std::uint32_t i = 0; i < 500; ++i) {
    TickRecord r = any_record(rng, i);
    r.has_second = true;
    const TickRecord other = any_record(rng, i);
    r.second.input = other.input;
    r.second.input.device_index = 1;
    std::copy(std::begin(other.force), std::end(other.force), std::begin(r.second.force));
    records.push_back(r);
  }
  const Bytes bytes = encode(records);
  ASSERT_EQ(bytes.size(), 2 * records.size() * kTickRecordSize);
  std::vector<TickRecord> decoded;
  ASSERT_EQ(decode_tick_records(bytes, decoded), "");
  ASSERT_EQ(decoded.size(), records.size());
  for (std::size_t i = 0; i < records.size(); ++i) {
    ASSERT_TRUE(decoded[i].has_second);
    ASSERT_TRUE(same_record(decoded[i], records[i])) << "record " << i;
    EXPECT_EQ(decoded[i].second.input, records[i].second.input) << "record " << i;
    for (int k = 0; k < 3; ++k)
      EXPECT_EQ(decoded[i].second.force[k], records[i].second.force[k]);
  }
  EXPECT_EQ(encode(decoded), bytes);

  // A one-handed tick among two-handed ones is refused.
  Bytes mixed(bytes.begin(), bytes.begin() + 2 * kTickRecordSize);
  mixed.insert(mixed.end(), bytes.begin() + 2 * kTickRecordSize,
               bytes.begin() + 3 * kTickRecordSize);  // tick 1's first hand only
  std::vector<TickRecord> mixed_out;
  EXPECT_EQ(decode_tick_records(mixed, mixed_out), "tick 1 has one hand, tick 0 had two");

  // A second hand's record alone, or after another tick's first, is refused.
  const Bytes second_first(bytes.begin() + kTickRecordSize, bytes.begin() + 2 * kTickRecordSize);
  std::vector<TickRecord> out;
  EXPECT_EQ(decode_tick_records(second_first, out),
            "a second hand's record for tick 0 does not follow that tick's first");
  Bytes twice(bytes.begin(), bytes.begin() + 2 * kTickRecordSize);
  twice.insert(twice.end(), bytes.begin() + kTickRecordSize, bytes.begin() + 2 * kTickRecordSize);
  out.clear();
  EXPECT_EQ(decode_tick_records(twice, out),
            "a second hand's record for tick 0 does not follow that tick's first");
}

TEST(TickRecord, EmptyChunkDecodesToNothing) {
  std::vector<TickRecord> out;
  EXPECT_EQ(decode_tick_records({}, out), "");
  EXPECT_TRUE(out.empty());
}

TEST(TickRecord, ChunkOfWrongSizeIsRejectedWithItsSize) {
  std::mt19937_64 rng(3);
  Bytes bytes = encode({any_record(rng, 0), any_record(rng, 1)});
  for (const std::size_t size :
       {std::size_t{1}, std::size_t{76}, std::size_t{78}, std::size_t{153}, std::size_t{155}}) {
    Bytes chunk = bytes;
    chunk.resize(size);
    std::vector<TickRecord> out;
    EXPECT_EQ(decode_tick_records(chunk, out),
              "chunk of " + std::to_string(size) +
                  " bytes is not a whole number of 77-byte tick records");
    EXPECT_TRUE(out.empty()) << size;  // the size is checked before anything is decoded
  }
}

TEST(TickRecord, NonConsecutiveTicksAreRejected) {
  std::mt19937_64 rng(4);
  for (const std::uint32_t second : {7u, 5u, 4u, 0u}) {  // a gap, a repeat, going back
    std::vector<TickRecord> out;
    EXPECT_EQ(decode_tick_records(encode({any_record(rng, 5), any_record(rng, second)}), out),
              "tick " + std::to_string(second) + " follows tick 5");
  }
}

TEST(TickRecord, ChunksDecodedInSequenceAppend) {
  std::mt19937_64 rng(5);
  std::vector<TickRecord> records;
  for (std::uint32_t i = 0; i < 30; ++i)
    records.push_back(any_record(rng, 100 + i));
  const std::vector<TickRecord> a(records.begin(), records.begin() + 10);
  const std::vector<TickRecord> b(records.begin() + 10, records.begin() + 11);
  const std::vector<TickRecord> c(records.begin() + 11, records.end());

  std::vector<TickRecord> out;
  ASSERT_EQ(decode_tick_records(encode(a), out), "");
  ASSERT_EQ(decode_tick_records({}, out), "");
  ASSERT_EQ(decode_tick_records(encode(b), out), "");
  ASSERT_EQ(decode_tick_records(encode(c), out), "");
  ASSERT_EQ(out.size(), records.size());
  for (std::size_t i = 0; i < records.size(); ++i)
    EXPECT_TRUE(same_record(out[i], records[i])) << i;

  // The tick sequence continues across chunks: a next chunk that skips a tick is rejected.
  std::vector<TickRecord> gap;
  ASSERT_EQ(decode_tick_records(encode(a), gap), "");
  EXPECT_EQ(decode_tick_records(encode(c), gap), "tick 111 follows tick 109");
}

}  // namespace
}  // namespace incise::server::live
