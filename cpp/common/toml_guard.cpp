// The TOML nesting guard (toml_guard.hpp).
#include "common/toml_guard.hpp"

#include <vector>

#include "common/error.hpp"
#include "common/location.hpp"

namespace pcsim {

void check_toml_nesting(const std::string& text, const std::filesystem::path& file) {
  // A scanner of TOML's structure, not a parser: it follows strings and comments, counts the
  // parts of each dotted key (in headers and before '=') and the nesting of arrays and inline
  // tables, and stops at the first excess, before the recursive parser ever sees the text.
  enum class Str { none, basic, literal, ml_basic, ml_literal };
  Str str = Str::none;
  std::vector<char> stack;        // open '[' / '{' of values (and of a header line)
  bool key_ctx = true, header = false, comment = false;
  int parts = 1, line = 1;
  std::string key_start;          // the first characters of the current key, for the message
  auto refuse = [&](const std::string& what) {
    throw InputError(input_location(file) + ":" + std::to_string(line) + ": key '" + key_start +
                     "...': expected at most " +
                     std::to_string(kMaxNesting) + " levels of nesting (pcsim files need at most 4), got " +
                     what);
  };
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\n') ++line;
    if (comment) {
      if (c == '\n') comment = false; else continue;
    }
    switch (str) {
      case Str::basic:
        if (c == '\\') ++i;
        else if (c == '"' || c == '\n') str = Str::none;
        continue;
      case Str::literal:
        if (c == '\'' || c == '\n') str = Str::none;
        continue;
      case Str::ml_basic:
        if (c == '\\') ++i;
        else if (text.compare(i, 3, "\"\"\"") == 0) { str = Str::none; i += 2; }
        continue;
      case Str::ml_literal:
        if (text.compare(i, 3, "'''") == 0) { str = Str::none; i += 2; }
        continue;
      case Str::none: break;
    }
    if (key_ctx && key_start.size() < 40 && c != ' ' && c != '\t' && c != '\n' && c != '[')
      key_start += c;
    switch (c) {
      case '#': comment = true; break;
      case '"':
        str = text.compare(i, 3, "\"\"\"") == 0 ? (i += 2, Str::ml_basic) : Str::basic;
        break;
      case '\'':
        str = text.compare(i, 3, "'''") == 0 ? (i += 2, Str::ml_literal) : Str::literal;
        break;
      case '.':
        if (key_ctx && ++parts > kMaxNesting) refuse(std::to_string(parts) + "+ dotted parts");
        break;
      case '=':
        key_ctx = false;
        break;
      case '[': case '{':
        if (stack.empty() && key_ctx && c == '[') {
          header = true;  // a table header: its dotted parts are counted like a key's
          break;
        }
        stack.push_back(c);
        if (static_cast<int>(stack.size()) > kMaxNesting)
          refuse(std::to_string(stack.size()) + "+ nested arrays or inline tables");
        key_ctx = c == '{';
        parts = 1;
        if (c == '{') key_start.clear();
        break;
      case ']': case '}':
        if (header && stack.empty()) { header = false; key_ctx = false; break; }
        if (!stack.empty()) stack.pop_back();
        break;
      case ',':
        if (!stack.empty() && stack.back() == '{') { key_ctx = true; parts = 1; key_start.clear(); }
        break;
      case '\n':
        if (stack.empty()) { key_ctx = true; header = false; parts = 1; key_start.clear(); }
        break;
      default: break;
    }
  }
}

}  // namespace pcsim
