// Lexing helpers shared by every text reader (.vm, points, mesh formats, TetGen's output, the
// script language): a bounds-checked cursor over text with line tracking, number parsing that
// never reads past the end, tokens shown safely in messages, and little-endian loads.
#pragma once

#include "frep/util/parse_number.hpp"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

#include "frep/error.hpp"

namespace frep::detail {

inline bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }
inline char lower(char c) { return (c >= 'A' && c <= 'Z') ? char(c - 'A' + 'a') : c; }
inline bool iequals(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (lower(a[i]) != lower(b[i])) return false;
  return true;
}
inline bool istarts_with(std::string_view s, std::string_view prefix) {
  return s.size() >= prefix.size() && iequals(s.substr(0, prefix.size()), prefix);
}

// Shows a token in an error message without dumping binary garbage or megabytes of it.
inline std::string printable(std::string_view s) {
  std::string out;
  for (char c : s.substr(0, 32)) {
    unsigned char u = static_cast<unsigned char>(c);
    if (u >= 32 && u < 127) out += c;
    else {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", u);
      out += buf;
    }
  }
  if (s.size() > 32) out += "...";
  return out;
}
// The same, in single quotes.
inline std::string quoted(std::string_view s) { return "'" + printable(s) + "'"; }

// Parses a whole token as a double ("+1", "1e5", "-.5"); false if it is not exactly a number.
inline bool parse_double(std::string_view tok, double& out) { return parse_real(tok, out); }

// Parses a whole token as a signed integer.
inline bool parse_int(std::string_view tok, std::int64_t& out) {
  const char* b = tok.data();
  const char* e = b + tok.size();
  if (b != e && *b == '+') ++b;
  if (b == e) return false;
  auto r = std::from_chars(b, e, out);
  return r.ec == std::errc() && r.ptr == e;
}

// Splits text into lines (LF, CRLF, or CR alone as old Mac files have when the text holds no LF),
// tracking 1-based line numbers and offsets.
class LineCursor {
 public:
  explicit LineCursor(std::string_view text)
      : text_(text), eol_(text.find('\n') == std::string_view::npos && text.find('\r') != std::string_view::npos ? '\r' : '\n') {}
  // Next line without its terminator; false at end of input.
  bool next(std::string_view& line) {
    if (pos_ >= text_.size()) return false;
    line_start_ = pos_;
    std::size_t eol = text_.find(eol_, pos_);
    if (eol == std::string_view::npos) eol = text_.size();
    line = text_.substr(pos_, eol - pos_);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos_ = eol + 1;
    ++line_no_;
    return true;
  }
  std::uint64_t line_no() const { return line_no_; }
  std::uint64_t line_offset() const { return line_start_; }
  std::size_t pos() const { return pos_; }

 private:
  std::string_view text_;
  char eol_;
  std::size_t pos_ = 0, line_start_ = 0;
  std::uint64_t line_no_ = 0;
};

// Splits one line into whitespace-separated tokens.
class TokenSplitter {
 public:
  explicit TokenSplitter(std::string_view line) : s_(line) {}
  bool next(std::string_view& tok) {
    while (i_ < s_.size() && is_space(s_[i_])) ++i_;
    if (i_ >= s_.size()) return false;
    std::size_t b = i_;
    while (i_ < s_.size() && !is_space(s_[i_])) ++i_;
    tok = s_.substr(b, i_ - b);
    return true;
  }
  std::string_view rest() const { return i_ < s_.size() ? s_.substr(i_) : std::string_view{}; }

 private:
  std::string_view s_;
  std::size_t i_ = 0;
};

// Whitespace-separated tokens across lines, with the line of the current token (for formats
// such as ASCII STL and ASCII PLY whose grammar is token based).
class TokenCursor {
 public:
  explicit TokenCursor(std::string_view text, std::size_t pos = 0, std::uint64_t line = 1)
      : text_(text), pos_(pos), line_(line), tok_line_(line) {}
  bool next(std::string_view& tok) {
    while (pos_ < text_.size() && (is_space(text_[pos_]) || text_[pos_] == '\n')) {
      if (ends_line(pos_)) ++line_;
      ++pos_;
    }
    if (pos_ >= text_.size()) return false;
    std::size_t b = pos_;
    while (pos_ < text_.size() && !is_space(text_[pos_]) && text_[pos_] != '\n') ++pos_;
    tok = text_.substr(b, pos_ - b);
    tok_line_ = line_;
    return true;
  }
  // Skips to the start of the next line (the rest of this one is free text, e.g. a solid name).
  void skip_line() {
    while (pos_ < text_.size() && !ends_line(pos_)) ++pos_;
  }
  // True when another token follows on the line of the last one.
  bool more_on_line() const {
    for (std::size_t p = pos_; p < text_.size() && !ends_line(p); ++p)
      if (!is_space(text_[p])) return true;
    return false;
  }
  std::uint64_t line() const { return tok_line_; }
  std::size_t pos() const { return pos_; }

 private:
  // A line ends at LF, or at a CR that no LF follows (old Mac files).
  bool ends_line(std::size_t p) const {
    return text_[p] == '\n' || (text_[p] == '\r' && (p + 1 == text_.size() || text_[p + 1] != '\n'));
  }

  std::string_view text_;
  std::size_t pos_ = 0;
  std::uint64_t line_ = 1, tok_line_ = 1;
};

inline std::uint32_t load_u32le(const char* p) {
  std::uint32_t v;
  std::memcpy(&v, p, 4);
  return v;  // x86-64 and every target we build for is little-endian
}
inline float load_f32le(const char* p) {
  float v;
  std::memcpy(&v, p, 4);
  return v;
}


}  // namespace frep::detail
