#pragma once

// A tiny streaming JSON writer for summary.json (no JSON library in the dependencies).

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <ostream>
#include <string>
#include <vector>

namespace rfm {
namespace offline {

class JsonWriter {
 public:
  explicit JsonWriter(std::ostream& out) : out_(out) {}

  JsonWriter& beginObject() { return open('{'); }
  JsonWriter& endObject() { return close('}'); }
  JsonWriter& beginArray() { return open('['); }
  JsonWriter& endArray() { return close(']'); }

  JsonWriter& key(const std::string& name) {
    separator();
    writeString(name);
    out_ << ": ";
    after_key_ = true;
    return *this;
  }
  JsonWriter& value(const std::string& text) {
    separator();
    writeString(text);
    return *this;
  }
  JsonWriter& value(const char* text) { return value(std::string(text)); }
  JsonWriter& value(bool flag) {
    separator();
    out_ << (flag ? "true" : "false");
    return *this;
  }
  JsonWriter& value(double number) {
    separator();
    if (!std::isfinite(number)) {
      out_ << "null";
    } else {
      char buffer[32];
      std::snprintf(buffer, sizeof(buffer), "%.10g", number);
      out_ << buffer;
    }
    return *this;
  }
  JsonWriter& value(int64_t number) {
    separator();
    out_ << number;
    return *this;
  }
  JsonWriter& value(uint64_t number) {
    separator();
    out_ << number;
    return *this;
  }
  JsonWriter& value(int number) { return value(static_cast<int64_t>(number)); }
  JsonWriter& value(unsigned number) { return value(static_cast<uint64_t>(number)); }

 private:
  JsonWriter& open(char bracket) {
    separator();
    out_ << bracket;
    first_.push_back(true);
    return *this;
  }
  JsonWriter& close(char bracket) {
    const bool empty = first_.back();
    first_.pop_back();
    if (!empty) newline();
    out_ << bracket;
    if (first_.empty()) out_ << '\n';
    return *this;
  }
  void separator() {
    if (after_key_) {
      after_key_ = false;
      return;
    }
    if (first_.empty()) return;
    if (!first_.back()) out_ << ',';
    first_.back() = false;
    newline();
  }
  void newline() {
    out_ << '\n';
    for (size_t i = 0; i < first_.size(); ++i)
      out_ << "  ";
  }
  void writeString(const std::string& text) {
    out_ << '"';
    for (const char c : text) {
      switch (c) {
        case '"':
          out_ << "\\\"";
          break;
        case '\\':
          out_ << "\\\\";
          break;
        case '\n':
          out_ << "\\n";
          break;
        case '\t':
          out_ << "\\t";
          break;
        case '\r':
          out_ << "\\r";
          break;
        default:
          if (static_cast<unsigned char>(c) < 0x20) {
            char buffer[8];
            std::snprintf(buffer, sizeof(buffer), "\\u%04x", static_cast<unsigned>(c));
            out_ << buffer;
          } else {
            out_ << c;
          }
      }
    }
    out_ << '"';
  }

  std::ostream& out_;
  std::vector<bool> first_;
  bool after_key_ = false;
};

}  // namespace offline
}  // namespace rfm
