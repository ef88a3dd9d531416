// The program's messages as a terminal shows them: a control byte in a message (from a file name,
// a scene's string, a checkpoint's key) is written as \xNN instead of acting on the terminal
// (ESC began a colour, BEL rang). Line ends, carriage returns (the progress line) and tabs pass.
#pragma once

#include <iosfwd>
#include <streambuf>

namespace silt::cli {

class EscapedOutput : public std::streambuf {
 public:
  // Filters `stream` (std::cout, std::cerr) until destroyed.
  explicit EscapedOutput(std::ostream& stream);
  ~EscapedOutput() override;
  EscapedOutput(const EscapedOutput&) = delete;
  EscapedOutput& operator=(const EscapedOutput&) = delete;

 protected:
  int overflow(int c) override;
  std::streamsize xsputn(const char* s, std::streamsize n) override;
  int sync() override;

 private:
  std::ostream& stream_;
  std::streambuf* out_;
};

}  // namespace silt::cli
