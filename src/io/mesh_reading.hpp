// Private to the mesh readers: the error helper and the checks every format
// shares once vertices and faces are in memory.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "nearcap/error.hpp"
#include "nearcap/scene/mesh.hpp"

namespace nearcap::mesh_reading {

// Throws Error(kind, "<source>: <what>").
[[noreturn]] void fail(ErrorKind kind, const std::string& source, const std::string& what);

// Every coordinate finite, at least one face, indices in range, three distinct
// vertices per face; throws naming the vertex or face.
void check_read_mesh(const TriangleMesh& mesh);

// "line N: what" errors of the line-oriented readers.
[[noreturn]] inline void fail_at_line(ErrorKind kind, const std::string& source, int line, const std::string& what) {
  fail(kind, source, "line " + std::to_string(line) + ": " + what);
}

// A word of the file as an error message shows it: its first 32 bytes, each
// byte that is not printable ASCII as '?'.
std::string printable(const std::string& word);

// Whether text[pos] ends a line: a line feed, or a carriage return not
// followed by one (the classic Mac OS line end; in "\r\n" the '\n' ends it).
inline bool is_line_end(const std::string& text, std::size_t pos) {
  return text[pos] == '\n' || (text[pos] == '\r' && (pos + 1 == text.size() || text[pos + 1] != '\n'));
}

// The end of the line that starts at `pos`: the index of its line end ("\n",
// "\r\n" or a lone "\r"), or text.size() for a last line without one; `next`
// gets the index after that line end.
std::size_t line_end(const std::string& text, std::size_t pos, std::size_t& next);

// The words of `line`: its runs of characters other than whitespace, in order.
std::vector<std::string> split_whitespace(const std::string& line);

// The words of a whole text mesh file, one at a time, with the line each is
// on (lines end as is_line_end says).  `comment`, unless '\0', starts a comment that runs to the end of its
// line and ends a word (OFF's '#').
class TextTokens {
 public:
  TextTokens(const std::string& text, const std::string& source, char comment = '\0')
      : text_(text), source_(source), comment_(comment) {}
  // The next word into `token`; false at the end of the text.
  bool next(std::string& token);
  // Skips to the end of the current line (values a reader ignores).
  void skip_rest_of_line();
  // The words left on the current line, up to its end or a comment.
  std::vector<std::string> rest_of_line();
  int line() const { return line_; }
  // Throws Error(Parse, "<source>: line N: <what>").
  [[noreturn]] void error(const std::string& what) const { fail_at_line(ErrorKind::Parse, source_, line_, what); }
  // The next word; at the end of the text, an error saying `what` was expected.
  std::string need(const std::string& what);

 private:
  bool is_comment(char c) const { return comment_ != '\0' && c == comment_; }
  const std::string& text_;
  const std::string& source_;
  char comment_;
  std::size_t pos_ = 0;
  int line_ = 1;
};

}  // namespace nearcap::mesh_reading
