// The tokens of a pbrt-v4 scene file (pbrt.org, "The pbrt-v4 file format"): quoted strings,
// brackets and bare words (directives, numbers, true/false); `#` starts a comment to the end
// of the line. Each token knows its line, for errors that name file and line.
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>

namespace hrpp {

struct PbrtToken {
  enum Kind { kWord, kString, kOpenBracket, kCloseBracket };
  Kind kind = kWord;
  std::string text;  // a string's contents, unquoted and unescaped
  int line = 0;
};

class PbrtTokenizer {
 public:
  // Reads the whole file; throws hrpp::Error "<file>: ..." when it cannot.
  explicit PbrtTokenizer(const std::filesystem::path& file);

  // The next token, or nothing at the end of the file. Throws hrpp::Error "<file>:<line>: ..."
  // on an unterminated string or a bad escape.
  std::optional<PbrtToken> next();
  // The next token without taking it.
  const std::optional<PbrtToken>& peek();

  const std::string& file() const { return name_; }
  int line() const { return line_; }  // the line the tokenizer has reached

 private:
  std::optional<PbrtToken> scan();
  PbrtToken scan_string();
  void skip_space_and_comments();

  std::string name_;
  std::string text_;
  std::size_t pos_ = 0;
  int line_ = 1;
  std::optional<PbrtToken> peeked_;
  bool has_peeked_ = false;
};

}  // namespace hrpp
