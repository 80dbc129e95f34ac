// PbrtTokenizer: pbrt-v4's lexical rules (src/pbrt/parser.cpp, Tokenizer::Next): whitespace
// separates tokens, `[` and `]` stand alone, a string runs to the next unescaped quote on the
// same line, `#` comments to the end of the line.
#include "scene/pbrt_tokenizer.h"

#include <fstream>
#include <sstream>

#include "common/error.h"

namespace hrpp {
namespace {

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

bool is_delimiter(char c) { return is_space(c) || c == '[' || c == ']' || c == '"' || c == '#'; }

}  // namespace

PbrtTokenizer::PbrtTokenizer(const std::filesystem::path& file) : name_(file.string()) {
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) throw Error(name_ + ": no such file");
  if (std::filesystem::is_directory(file, ec)) throw Error(name_ + ": is a directory");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error(name_ + ": cannot open for reading");
  std::stringstream ss;
  ss << in.rdbuf();
  text_ = ss.str();
}

std::optional<PbrtToken> PbrtTokenizer::next() {
  if (has_peeked_) {
    has_peeked_ = false;
    return std::move(peeked_);
  }
  return scan();
}

const std::optional<PbrtToken>& PbrtTokenizer::peek() {
  if (!has_peeked_) {
    peeked_ = scan();
    has_peeked_ = true;
  }
  return peeked_;
}

void PbrtTokenizer::skip_space_and_comments() {
  while (pos_ < text_.size()) {
    const char c = text_[pos_];
    if (c == '\n') {
      ++line_;
      ++pos_;
    } else if (is_space(c)) {
      ++pos_;
    } else if (c == '#') {
      while (pos_ < text_.size() && text_[pos_] != '\n') ++pos_;
    } else {
      return;
    }
  }
}

std::optional<PbrtToken> PbrtTokenizer::scan() {
  skip_space_and_comments();
  if (pos_ >= text_.size()) return std::nullopt;
  const char c = text_[pos_];
  if (c == '[' || c == ']') {
    ++pos_;
    return PbrtToken{c == '[' ? PbrtToken::kOpenBracket : PbrtToken::kCloseBracket,
                     std::string(1, c), line_};
  }
  if (c == '"') return scan_string();
  const std::size_t start = pos_;
  while (pos_ < text_.size() && !is_delimiter(text_[pos_])) ++pos_;
  return PbrtToken{PbrtToken::kWord, text_.substr(start, pos_ - start), line_};
}

PbrtToken PbrtTokenizer::scan_string() {
  PbrtToken t{PbrtToken::kString, "", line_};
  ++pos_;  // the opening quote
  while (true) {
    if (pos_ >= text_.size() || text_[pos_] == '\n') {
      throw Error(name_ + ":" + std::to_string(t.line) + ": unterminated string");
    }
    const char c = text_[pos_++];
    if (c == '"') return t;
    if (c != '\\') {
      t.text += c;
      continue;
    }
    if (pos_ >= text_.size())
      throw Error(name_ + ":" + std::to_string(line_) + ": unterminated string");
    const char e = text_[pos_++];
    switch (e) {
      case 'b':
        t.text += '\b';
        break;
      case 'f':
        t.text += '\f';
        break;
      case 'n':
        t.text += '\n';
        break;
      case 'r':
        t.text += '\r';
        break;
      case 't':
        t.text += '\t';
        break;
      case '\\':
        t.text += '\\';
        break;
      case '\'':
        t.text += '\'';
        break;
      case '"':
        t.text += '"';
        break;
      default:
        throw Error(name_ + ":" + std::to_string(line_) + ": unexpected escape \\" +
                    std::string(1, e) + " in a string");
    }
  }
}

}  // namespace hrpp
