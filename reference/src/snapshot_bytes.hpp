// Little-endian bytes for snapshots (docs/SNAPSHOTS.md): a writer into a
// buffer sized in advance, a bounds-checked reader that throws SnapshotError
// naming the field it was reading, LEB128 varints, and the checksum. Every
// access goes through memcpy and a bounds check: no casts of the buffer, no
// reads past its end.
#pragma once
#include <bit>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "lockstep/snapshot.hpp"

namespace lockstep::snap {

// Appends to a byte vector. reserve() the bound first; put() grows it if the
// bound was short (never UB, only slower).
class Writer {
 public:
  explicit Writer(std::vector<std::uint8_t>& out) : out_(out) {}
  void bytes(const void* p, std::size_t n) {
    const std::size_t at = out_.size();
    out_.resize(at + n);
    if (n != 0) std::memcpy(out_.data() + at, p, n);
  }
  void u8(std::uint8_t v) { out_.push_back(v); }
  void u16(std::uint16_t v) { le(v, 2); }
  void u32(std::uint32_t v) { le(v, 4); }
  void u64(std::uint64_t v) { le(v, 8); }
  void i32(std::int32_t v) { u32(static_cast<std::uint32_t>(v)); }
  void f64(double d) {
    std::uint64_t u;
    std::memcpy(&u, &d, sizeof u);
    u64(u);
  }
  void varint(std::uint64_t v) {
    while (v >= 0x80) {
      out_.push_back(static_cast<std::uint8_t>(v | 0x80));
      v >>= 7;
    }
    out_.push_back(static_cast<std::uint8_t>(v));
  }
  void svarint(std::int64_t v) {  // zigzag
    varint((static_cast<std::uint64_t>(v) << 1) ^ static_cast<std::uint64_t>(v < 0 ? -1 : 0));
  }
  void string(const std::string& s) {
    u32(static_cast<std::uint32_t>(s.size()));
    bytes(s.data(), s.size());
  }
  std::size_t size() const { return out_.size(); }
  std::vector<std::uint8_t>& buffer() { return out_; }

 private:
  void le(std::uint64_t v, int n) {
    std::uint8_t b[8];
    for (int i = 0; i < n; ++i) b[i] = static_cast<std::uint8_t>(v >> (8 * i));
    bytes(b, static_cast<std::size_t>(n));
  }
  std::vector<std::uint8_t>& out_;
};

// Writes through a pointer into space the caller has sized (the per-body
// section: its bound is computed first, then the buffer is cut to what was
// written). The caller guarantees the room; each put is one memcpy-free
// little-endian store sequence.
struct Cursor {
  std::uint8_t* p;
  void u8(std::uint8_t v) { *p++ = v; }
  void u32(std::uint32_t v) { store(v); }
  void u64(std::uint64_t v) { store(v); }
  // One memcpy on a little-endian host (the bytes are the value's), byte by
  // byte elsewhere.
  template <class U>
  void store(U v) {
    if constexpr (std::endian::native == std::endian::little) {
      std::memcpy(p, &v, sizeof v);
      p += sizeof v;
    } else {
      for (std::size_t i = 0; i < sizeof v; ++i) *p++ = static_cast<std::uint8_t>(v >> (8 * i));
    }
  }
  void varint(std::uint64_t v) {
    while (v >= 0x80) {
      *p++ = static_cast<std::uint8_t>(v | 0x80);
      v >>= 7;
    }
    *p++ = static_cast<std::uint8_t>(v);
  }
  void svarint(std::int64_t v) { varint((static_cast<std::uint64_t>(v) << 1) ^ static_cast<std::uint64_t>(v < 0 ? -1 : 0)); }
};
inline constexpr std::size_t kMaxVarint = 10;

// Reads [data, data + size); every read names the field it is for, so that
// a truncated snapshot says what was cut.
class Reader {
 public:
  Reader(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  std::size_t pos() const { return pos_; }
  std::size_t left() const { return size_ - pos_; }
  const std::uint8_t* need(std::size_t n, const char* field) {
    if (n > left()) [[unlikely]]
      truncated(n, field);
    const std::uint8_t* p = data_ + pos_;
    pos_ += n;
    return p;
  }
  [[noreturn]] void truncated(std::size_t n, const char* field) const {
    throw SnapshotError("truncated: " + std::string(field) + " needs " + std::to_string(n) + " bytes at offset " +
                              std::to_string(pos_) + ", " + std::to_string(left()) + " left",
                          field);
  }
  std::uint8_t u8(const char* field) { return *need(1, field); }
  std::uint16_t u16(const char* field) { return static_cast<std::uint16_t>(le(2, field)); }
  std::uint32_t u32(const char* field) { return static_cast<std::uint32_t>(le(4, field)); }
  std::uint64_t u64(const char* field) { return le(8, field); }
  std::int32_t i32(const char* field) {
    const std::uint32_t u = u32(field);
    std::int32_t v;
    std::memcpy(&v, &u, sizeof v);
    return v;
  }
  double f64(const char* field) {
    const std::uint64_t u = u64(field);
    double d;
    std::memcpy(&d, &u, sizeof d);
    return d;
  }
  std::uint64_t varint(const char* field) {
    std::uint64_t v = 0;
    for (int shift = 0; shift < 64; shift += 7) {
      const std::uint8_t b = u8(field);
      if (shift == 63 && b > 1) break;
      v |= static_cast<std::uint64_t>(b & 0x7f) << shift;
      if ((b & 0x80) == 0) return v;
    }
    throw SnapshotError(std::string(field) + ": malformed varint (over 64 bits) at offset " + std::to_string(pos_),
                        field);
  }
  std::int64_t svarint(const char* field) {
    const std::uint64_t u = varint(field);
    return static_cast<std::int64_t>(u >> 1) ^ -static_cast<std::int64_t>(u & 1);
  }
  std::string string(const char* field, std::size_t max_len) {
    const std::uint32_t n = u32(field);
    if (n > max_len)
      throw SnapshotError(std::string(field) + ": length " + std::to_string(n) + " exceeds " + std::to_string(max_len),
                          field);
    const std::uint8_t* p = need(n, field);
    return std::string(reinterpret_cast<const char*>(p), n);
  }

 private:
  std::uint64_t le(int n, const char* field) {
    const std::uint8_t* p = need(static_cast<std::size_t>(n), field);
    if constexpr (std::endian::native == std::endian::little) {
      if (n == 4) {
        std::uint32_t v;
        std::memcpy(&v, p, 4);
        return v;
      }
      if (n == 8) {
        std::uint64_t v;
        std::memcpy(&v, p, 8);
        return v;
      }
    }
    std::uint64_t v = 0;
    for (int i = 0; i < n; ++i) v |= static_cast<std::uint64_t>(p[i]) << (8 * i);
    return v;
  }
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

// The trailer's checksum (docs/SNAPSHOTS.md "Checksum"): the bytes as
// little-endian 64-bit words (the last one padded with zeros), word k folded
// into lane k mod 4 by h = (h ^ w) * FNV_PRIME from FNV_OFFSET; then FNV-1a 64
// over the 4 lanes' 32 little-endian bytes and the 8 bytes of the length.
std::uint64_t checksum(const std::uint8_t* data, std::size_t size);

// FNV-1a 64 over bytes.
std::uint64_t fnv1a(const std::uint8_t* data, std::size_t size, std::uint64_t h = 0xcbf29ce484222325ull);

}  // namespace lockstep::snap
