#pragma once
// Byte-wise little-endian loads and stores: the wire format is the same on every host, and the
// fields of a frame need no alignment.

#include <bit>
#include <concepts>
#include <cstddef>
#include <cstdint>

namespace incise::devices {

// Writes the sizeof(T) bytes of value to out[0..sizeof(T)), least significant first.
template <std::unsigned_integral T>
constexpr void store_le(T value, uint8_t* out) {
  for (std::size_t i = 0; i < sizeof(T); ++i) {
    out[i] = static_cast<uint8_t>(value >> (8 * i));
  }
}

// Reads sizeof(T) bytes from in[0..sizeof(T)), least significant first.
template <std::unsigned_integral T>
constexpr T load_le(const uint8_t* in) {
  T value = 0;
  for (std::size_t i = 0; i < sizeof(T); ++i) {
    value = static_cast<T>(value | (static_cast<T>(in[i]) << (8 * i)));
  }
  return value;
}

// IEEE 754 values travel as the little-endian bytes of their bit pattern, so NaN payloads and
// signed zeros survive the round trip.
inline void store_le_f32(float value, uint8_t* out) {
  store_le(std::bit_cast<uint32_t>(value), out);
}
inline void store_le_f64(double value, uint8_t* out) {
  store_le(std::bit_cast<uint64_t>(value), out);
}
inline float load_le_f32(const uint8_t* in) {
  return std::bit_cast<float>(load_le<uint32_t>(in));
}
inline double load_le_f64(const uint8_t* in) {
  return std::bit_cast<double>(load_le<uint64_t>(in));
}

}  // namespace incise::devices
