#include "json_value.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace bakegi::cli {
namespace {

class Parser {
 public:
  explicit Parser(const std::string& text) : text_(text) {}

  JsonValue parse_document() {
    JsonValue v = parse_value();
    skip_space();
    if (at_ < text_.size()) fail("trailing characters");
    return v;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw JsonError("JSON: " + what + " at offset " + std::to_string(at_));
  }
  void skip_space() {
    while (at_ < text_.size() &&
           (text_[at_] == ' ' || text_[at_] == '\n' || text_[at_] == '\r' || text_[at_] == '\t')) {
      ++at_;
    }
  }
  char peek() {
    skip_space();
    if (at_ >= text_.size()) fail("unexpected end");
    return text_[at_];
  }
  void expect(char c) {
    if (peek() != c) fail(std::string("expected '") + c + "'");
    ++at_;
  }
  bool consume_word(const char* word) {
    const std::string w(word);
    if (text_.compare(at_, w.size(), w) != 0) return false;
    at_ += w.size();
    return true;
  }

  JsonValue parse_value() {
    // Bounded nesting: the report is shallow, and a deep input must not blow the stack.
    if (++depth_ > 64) fail("nesting too deep");
    JsonValue v;
    const char c = peek();
    if (c == '{') {
      v.value = parse_object();
    } else if (c == '[') {
      v.value = parse_array();
    } else if (c == '"') {
      v.value = parse_string();
    } else if (consume_word("true")) {
      v.value = true;
    } else if (consume_word("false")) {
      v.value = false;
    } else if (consume_word("null")) {
      v.value = nullptr;
    } else {
      v.value = parse_number();
    }
    --depth_;
    return v;
  }

  JsonValue::Object parse_object() {
    JsonValue::Object object;
    expect('{');
    if (peek() == '}') {
      ++at_;
      return object;
    }
    while (true) {
      if (peek() != '"') fail("expected a key");
      std::string key = parse_string();
      expect(':');
      object[key] = parse_value();
      if (peek() == ',') {
        ++at_;
        continue;
      }
      expect('}');
      return object;
    }
  }

  JsonValue::Array parse_array() {
    JsonValue::Array array;
    expect('[');
    if (peek() == ']') {
      ++at_;
      return array;
    }
    while (true) {
      array.push_back(parse_value());
      if (peek() == ',') {
        ++at_;
        continue;
      }
      expect(']');
      return array;
    }
  }

  std::string parse_string() {
    expect('"');
    std::string out;
    while (at_ < text_.size() && text_[at_] != '"') {
      char c = text_[at_++];
      if (c != '\\') {
        out += c;
        continue;
      }
      if (at_ >= text_.size()) fail("unterminated escape");
      c = text_[at_++];
      switch (c) {
        case 'n':
          out += '\n';
          break;
        case 't':
          out += '\t';
          break;
        case 'r':
          out += '\r';
          break;
        case 'b':
          out += '\b';
          break;
        case 'f':
          out += '\f';
          break;
        case 'u': {
          if (at_ + 4 > text_.size()) fail("short \\u escape");
          const unsigned code = std::stoul(text_.substr(at_, 4), nullptr, 16);
          at_ += 4;
          // Messages are ASCII; anything else is kept as UTF-8 for the BMP.
          if (code < 0x80) {
            out += static_cast<char>(code);
          } else if (code < 0x800) {
            out += static_cast<char>(0xC0 | (code >> 6));
            out += static_cast<char>(0x80 | (code & 0x3F));
          } else {
            out += static_cast<char>(0xE0 | (code >> 12));
            out += static_cast<char>(0x80 | ((code >> 6) & 0x3F));
            out += static_cast<char>(0x80 | (code & 0x3F));
          }
          break;
        }
        default:
          out += c;  // \" \\ \/
      }
    }
    if (at_ >= text_.size()) fail("unterminated string");
    ++at_;
    return out;
  }

  double parse_number() {
    const char* begin = text_.c_str() + at_;
    char* end = nullptr;
    const double v = std::strtod(begin, &end);
    if (end == begin) fail("unexpected character");
    at_ += static_cast<size_t>(end - begin);
    return v;
  }

  const std::string& text_;
  size_t at_ = 0;
  int depth_ = 0;
};

}  // namespace

JsonValue JsonValue::parse(const std::string& text) {
  return Parser(text).parse_document();
}

const JsonValue* JsonValue::find(const std::string& key) const {
  const auto* object = std::get_if<Object>(&value);
  if (!object) return nullptr;
  const auto it = object->find(key);
  return it == object->end() ? nullptr : &it->second;
}

const JsonValue* JsonValue::find_path(const std::vector<std::string>& path) const {
  const JsonValue* v = this;
  for (const auto& key : path) {
    v = v->find(key);
    if (!v) return nullptr;
  }
  return v;
}

std::optional<double> JsonValue::number() const {
  if (const auto* d = std::get_if<double>(&value)) return *d;
  return std::nullopt;
}

std::optional<std::string> JsonValue::string() const {
  if (const auto* s = std::get_if<std::string>(&value)) return *s;
  return std::nullopt;
}

}  // namespace bakegi::cli
