// SPDX-License-Identifier: Apache-2.0
#pragma once
// Internal to io/ros_messages.cc: cursors over a serialized ROS message, one that reads and one
// that writes, with the same member names so that one field walker per message type (written
// once, in field order) serves decoding and encoding on both wires.
//
// ROS 1: little-endian, no alignment, strings = uint32 byte count + bytes (no NUL), variable
// arrays = uint32 element count + elements, time = uint32 sec + uint32 nsec.
// CDR (XCDR1, as ROS 2 writes it): a 4-byte encapsulation header {0x00, 0x01 = little endian |
// 0x00 = big endian, options, options}; each primitive aligned to its size counted from the
// byte after that header; strings = uint32 count including the terminating NUL + bytes + NUL;
// sequences = uint32 count + elements; time = int32 sec + uint32 nanosec.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include "recording/ros/ros_messages.h"

namespace wallcal::recording::wire {

// Reads fields in order. After the first failure every call is a no-op and the failure (kind,
// byte offset in the payload, what was being read) is kept for Finish().
class Reader {
 public:
  Reader(const uint8_t* data, size_t size, WireFormat wire)
      : data_(data), size_(size), wire_(wire) {
    if (wire_ == WireFormat::kCdr) ReadEncapsulation();
  }

  WireFormat wire() const { return wire_; }

  template <class T>
  void Prim(T& value, const char* what) {
    static_assert(std::is_arithmetic_v<T>, "primitives only");
    if (!Align(sizeof(T), what) || !Need(sizeof(T), what, "")) return;
    value = Load<T>(pos_);
    pos_ += sizeof(T);
  }

  // Builtin time as seconds: ROS 1 uint32 sec + uint32 nsec, CDR int32 sec + uint32 nanosec.
  void Time(double& stamp_s, const char* what) {
    uint32_t nsec = 0;
    if (wire_ == WireFormat::kRos1) {
      uint32_t sec = 0;
      Prim(sec, what);
      Prim(nsec, what);
      stamp_s = static_cast<double>(sec) + 1e-9 * static_cast<double>(nsec);
    } else {
      int32_t sec = 0;
      Prim(sec, what);
      Prim(nsec, what);
      stamp_s = static_cast<double>(sec) + 1e-9 * static_cast<double>(nsec);
    }
  }

  void String(std::string& text, const char* what) {
    uint32_t count = 0;
    Prim(count, what);
    if (failed() || !Need(count, what, " (string bytes)")) return;
    const char* bytes = reinterpret_cast<const char*>(data_ + pos_);
    size_t length = count;
    if (wire_ == WireFormat::kCdr && count > 0) {
      if (bytes[count - 1] != '\0') {
        Fail(DecodeFailure::kBadLength, std::string(what) + ": CDR string of " +
                                            std::to_string(count) + " bytes lacks its NUL");
        return;
      }
      length = count - 1;  // the NUL is counted but is not part of the text
    }
    text.assign(bytes, length);
    pos_ += count;
  }

  template <class T>
  void Seq(std::vector<T>& values, const char* what) {
    uint32_t count = 0;
    Prim(count, what);
    if (failed()) return;
    // Checked before any allocation: a hostile count of 4e9 fails here, not in resize().
    if (count > 0 && !Align(sizeof(T), what)) return;
    if (!Need(static_cast<uint64_t>(count) * sizeof(T), what,
              " (" + std::to_string(count) + " elements)"))
      return;
    values.resize(count);
    for (uint32_t i = 0; i < count; ++i) {
      values[i] = Load<T>(pos_);
      pos_ += sizeof(T);
    }
  }

  template <class T, size_t N>
  void Array(T (&values)[N], const char* what) {
    for (size_t i = 0; i < N; ++i) Prim(values[i], what);
  }

  // The outcome: the first failure, else trailing bytes beyond what CDR pads (3), else success.
  DecodeResult Finish() {
    if (failed()) return result_;
    const size_t left = size_ - pos_;
    const size_t allowed = wire_ == WireFormat::kCdr ? 3 : 0;
    if (left > allowed) {
      result_.failure = DecodeFailure::kTrailingBytes;
      result_.offset = pos_;
      result_.detail = std::to_string(left) + " bytes after the last field";
    }
    return result_;
  }

 private:
  bool failed() const { return result_.failure != DecodeFailure::kNone; }

  void Fail(DecodeFailure failure, std::string detail) {
    result_.failure = failure;
    result_.offset = pos_;
    result_.detail = std::move(detail);
  }

  void ReadEncapsulation() {
    if (size_ < 4) {
      Fail(DecodeFailure::kTooShort,
           "CDR encapsulation header: 4 bytes, " + std::to_string(size_) + " present");
      return;
    }
    if (data_[0] != 0x00 || data_[1] > 0x01) {
      Fail(DecodeFailure::kBadEncapsulation,
           "CDR encapsulation " + std::to_string(data_[0]) + "," + std::to_string(data_[1]) +
               ": expected 0,1 (little-endian XCDR1) or 0,0 (big-endian XCDR1)");
      return;
    }
    big_endian_ = data_[1] == 0x00;
    pos_ = 4;
    origin_ = 4;
  }

  bool Align(size_t alignment, const char* what) {
    if (failed()) return false;
    if (wire_ != WireFormat::kCdr) return true;
    const size_t pad = (alignment - (pos_ - origin_) % alignment) % alignment;
    if (!Need(pad, what, " (alignment padding)")) return false;
    pos_ += pad;
    return true;
  }

  bool Need(uint64_t bytes, const char* what, const std::string& note) {
    if (failed()) return false;
    if (bytes <= size_ - pos_) return true;
    Fail(DecodeFailure::kTooShort, std::string(what) + note + ": " + std::to_string(bytes) +
                                       " bytes needed, " + std::to_string(size_ - pos_) + " left");
    return false;
  }

  template <class T>
  T Load(size_t at) const {
    uint64_t bits = 0;
    for (size_t i = 0; i < sizeof(T); ++i) {
      const size_t shift = big_endian_ ? 8 * (sizeof(T) - 1 - i) : 8 * i;
      bits |= static_cast<uint64_t>(data_[at + i]) << shift;
    }
    T value;
    if constexpr (sizeof(T) == 1) {
      const uint8_t b = static_cast<uint8_t>(bits);
      std::memcpy(&value, &b, 1);
    } else if constexpr (sizeof(T) == 2) {
      const uint16_t b = static_cast<uint16_t>(bits);
      std::memcpy(&value, &b, 2);
    } else if constexpr (sizeof(T) == 4) {
      const uint32_t b = static_cast<uint32_t>(bits);
      std::memcpy(&value, &b, 4);
    } else {
      std::memcpy(&value, &bits, 8);
    }
    return value;
  }

  const uint8_t* data_;
  size_t size_;
  WireFormat wire_;
  size_t pos_ = 0;
  size_t origin_ = 0;  // CDR alignment counts from here (the byte after the encapsulation)
  bool big_endian_ = false;
  DecodeResult result_;
};

// Writes fields in order: ROS 1, or little-endian CDR with its encapsulation header.
class Writer {
 public:
  explicit Writer(WireFormat wire) : wire_(wire) {
    if (wire_ == WireFormat::kCdr) out_ = {0x00, 0x01, 0x00, 0x00};
  }

  WireFormat wire() const { return wire_; }

  template <class T>
  void Prim(const T& value, const char* /*what*/) {
    static_assert(std::is_arithmetic_v<T>, "primitives only");
    Align(sizeof(T));
    uint64_t bits = 0;  // the value's bit pattern as an integer, written low byte first
    if constexpr (sizeof(T) == 1) {
      uint8_t b;
      std::memcpy(&b, &value, 1);
      bits = b;
    } else if constexpr (sizeof(T) == 2) {
      uint16_t b;
      std::memcpy(&b, &value, 2);
      bits = b;
    } else if constexpr (sizeof(T) == 4) {
      uint32_t b;
      std::memcpy(&b, &value, 4);
      bits = b;
    } else {
      std::memcpy(&bits, &value, 8);
    }
    for (size_t i = 0; i < sizeof(T); ++i) out_.push_back(static_cast<uint8_t>(bits >> (8 * i)));
  }

  // Seconds rounded to the nearest nanosecond. ROS 1 time is unsigned: a negative or
  // non-finite stamp is written as 0, a stamp beyond 2^32 s as the largest time.
  void Time(const double& stamp_s, const char* what) {
    double whole = std::isfinite(stamp_s) ? std::floor(stamp_s) : 0.0;
    int64_t nsec = std::isfinite(stamp_s) ? std::llround((stamp_s - whole) * 1e9) : 0;
    if (nsec >= 1000000000) {
      whole += 1.0;
      nsec -= 1000000000;
    }
    if (wire_ == WireFormat::kRos1) {
      if (whole < 0.0) {
        whole = 0.0;
        nsec = 0;
      }
      if (whole > 4294967295.0) {
        whole = 4294967295.0;
        nsec = 999999999;
      }
      Prim(static_cast<uint32_t>(whole), what);
    } else {
      if (whole < -2147483648.0) {
        whole = -2147483648.0;
        nsec = 0;
      }
      if (whole > 2147483647.0) {
        whole = 2147483647.0;
        nsec = 999999999;
      }
      Prim(static_cast<int32_t>(whole), what);
    }
    Prim(static_cast<uint32_t>(nsec), what);
  }

  void String(const std::string& text, const char* what) {
    const bool cdr = wire_ == WireFormat::kCdr;
    Prim(static_cast<uint32_t>(text.size() + (cdr ? 1 : 0)), what);
    out_.insert(out_.end(), text.begin(), text.end());
    if (cdr) out_.push_back(0);
  }

  template <class T>
  void Seq(const std::vector<T>& values, const char* what) {
    Prim(static_cast<uint32_t>(values.size()), what);
    for (const T& v : values) Prim(v, what);
  }

  template <class T, size_t N>
  void Array(const T (&values)[N], const char* what) {
    for (size_t i = 0; i < N; ++i) Prim(values[i], what);
  }

  std::vector<uint8_t> Take() { return std::move(out_); }

 private:
  void Align(size_t alignment) {
    if (wire_ != WireFormat::kCdr) return;
    while ((out_.size() - 4) % alignment != 0) out_.push_back(0);
  }

  WireFormat wire_;
  std::vector<uint8_t> out_;
};

}  // namespace wallcal::recording::wire
