#include "shell/escaped_output.hpp"

#include <ostream>

#include "silt/text.hpp"

namespace silt::cli {
namespace {

bool passes(char c) { return !is_control(c) || c == '\n' || c == '\r' || c == '\t'; }

}  // namespace

EscapedOutput::EscapedOutput(std::ostream& stream) : stream_(stream), out_(stream.rdbuf(this)) {}

EscapedOutput::~EscapedOutput() { stream_.rdbuf(out_); }

int EscapedOutput::overflow(int c) {
  if (c == traits_type::eof()) return traits_type::not_eof(c);
  const char ch = traits_type::to_char_type(c);
  if (passes(ch)) return out_->sputc(ch) == traits_type::eof() ? traits_type::eof() : c;
  constexpr char kHex[] = "0123456789abcdef";
  const auto b = static_cast<unsigned char>(ch);
  const char escaped[4] = {'\\', 'x', kHex[b >> 4], kHex[b & 15]};
  return out_->sputn(escaped, 4) == 4 ? c : traits_type::eof();
}

std::streamsize EscapedOutput::xsputn(const char* s, std::streamsize n) {
  std::streamsize done = 0;
  while (done < n) {
    std::streamsize run = 0;  // bytes that pass, written at once
    while (done + run < n && passes(s[done + run])) ++run;
    if (run > 0 && out_->sputn(s + done, run) != run) return done;
    done += run;
    if (done < n) {
      if (overflow(traits_type::to_int_type(s[done])) == traits_type::eof()) return done;
      ++done;
    }
  }
  return done;
}

int EscapedOutput::sync() { return out_->pubsync(); }

}  // namespace silt::cli
