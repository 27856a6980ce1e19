// SPDX-License-Identifier: Apache-2.0
#pragma once
// A strict little JSON parser for the tests that read what --emit json prints (one scanner
// or several). A missing key is a test failure, and reads as null.

#include <gtest/gtest.h>

#include <cctype>
#include <map>
#include <string>
#include <vector>

namespace wallcal::testing_support {

// A strict little JSON parser (RFC 8259 subset: no \u surrogate handling needed here).
struct Json {
  enum Kind { kNull, kBool, kNumber, kString, kArray, kObject } kind = kNull;
  bool b = false;
  double number = 0;
  std::string text;
  std::vector<Json> items;
  std::map<std::string, Json> members;
  const Json& operator[](const std::string& key) const {
    static const Json missing;
    const auto it = members.find(key);
    EXPECT_NE(it, members.end()) << "missing key " << key;
    return it == members.end() ? missing : it->second;
  }
};

class JsonParser {
 public:
  explicit JsonParser(const std::string& s) : s_(s) {}
  bool Parse(Json* out) {
    if (!Value(out)) return false;
    Space();
    return p_ == s_.size();
  }

 private:
  void Space() {
    while (p_ < s_.size() && (s_[p_] == ' ' || s_[p_] == '\n' || s_[p_] == '\t' || s_[p_] == '\r')) ++p_;
  }
  bool Literal(const char* word) {
    const std::string w(word);
    if (s_.compare(p_, w.size(), w) != 0) return false;
    p_ += w.size();
    return true;
  }
  bool String(std::string* out) {
    if (p_ >= s_.size() || s_[p_] != '"') return false;
    ++p_;
    while (p_ < s_.size() && s_[p_] != '"') {
      if (static_cast<unsigned char>(s_[p_]) < 0x20) return false;
      if (s_[p_] == '\\') {
        if (++p_ >= s_.size()) return false;
        const char c = s_[p_];
        if (c == 'u') {
          if (p_ + 4 >= s_.size()) return false;
          *out += '?';
          p_ += 4;
        } else if (std::string("\"\\/bfnrt").find(c) != std::string::npos) {
          *out += c;
        } else {
          return false;
        }
        ++p_;
        continue;
      }
      *out += s_[p_++];
    }
    if (p_ >= s_.size()) return false;
    ++p_;
    return true;
  }
  bool Value(Json* v) {
    Space();
    if (p_ >= s_.size()) return false;
    const char c = s_[p_];
    if (c == '{') {
      v->kind = Json::kObject;
      ++p_;
      Space();
      if (p_ < s_.size() && s_[p_] == '}') return ++p_, true;
      while (true) {
        Space();
        std::string key;
        if (!String(&key)) return false;
        if (v->members.count(key)) return false;  // duplicate key
        Space();
        if (p_ >= s_.size() || s_[p_++] != ':') return false;
        if (!Value(&v->members[key])) return false;
        Space();
        if (p_ >= s_.size()) return false;
        if (s_[p_] == ',') { ++p_; continue; }
        if (s_[p_] == '}') return ++p_, true;
        return false;
      }
    }
    if (c == '[') {
      v->kind = Json::kArray;
      ++p_;
      Space();
      if (p_ < s_.size() && s_[p_] == ']') return ++p_, true;
      while (true) {
        v->items.emplace_back();
        if (!Value(&v->items.back())) return false;
        Space();
        if (p_ >= s_.size()) return false;
        if (s_[p_] == ',') { ++p_; continue; }
        if (s_[p_] == ']') return ++p_, true;
        return false;
      }
    }
    if (c == '"') {
      v->kind = Json::kString;
      return String(&v->text);
    }
    if (Literal("null")) return v->kind = Json::kNull, true;
    if (Literal("true")) return v->kind = Json::kBool, v->b = true, true;
    if (Literal("false")) return v->kind = Json::kBool, v->b = false, true;
    // Number: -?(0|[1-9][0-9]*)(.[0-9]+)?([eE][+-]?[0-9]+)?
    const size_t start = p_;
    if (s_[p_] == '-') ++p_;
    if (p_ >= s_.size() || !std::isdigit(static_cast<unsigned char>(s_[p_]))) return false;
    if (s_[p_] == '0') {
      ++p_;
    } else {
      while (p_ < s_.size() && std::isdigit(static_cast<unsigned char>(s_[p_]))) ++p_;
    }
    if (p_ < s_.size() && s_[p_] == '.') {
      ++p_;
      if (p_ >= s_.size() || !std::isdigit(static_cast<unsigned char>(s_[p_]))) return false;
      while (p_ < s_.size() && std::isdigit(static_cast<unsigned char>(s_[p_]))) ++p_;
    }
    if (p_ < s_.size() && (s_[p_] == 'e' || s_[p_] == 'E')) {
      ++p_;
      if (p_ < s_.size() && (s_[p_] == '+' || s_[p_] == '-')) ++p_;
      if (p_ >= s_.size() || !std::isdigit(static_cast<unsigned char>(s_[p_]))) return false;
      while (p_ < s_.size() && std::isdigit(static_cast<unsigned char>(s_[p_]))) ++p_;
    }
    v->kind = Json::kNumber;
    v->number = std::stod(s_.substr(start, p_ - start));
    return true;
  }

  const std::string& s_;
  size_t p_ = 0;
};

}  // namespace wallcal::testing_support
