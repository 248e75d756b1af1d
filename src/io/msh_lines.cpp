#include "io/msh_lines.h"

#include <charconv>
#include <fstream>
#include <string_view>
#include <vector>

#include "core/errors.h"
#include "io/text.h"

namespace stickslip {
namespace {

// Lines of a file read one at a time with their 1-based numbers.
class LineReader {
 public:
  explicit LineReader(std::istream& in) : in_(in) {}
  bool next(std::string* line) {
    if (!std::getline(in_, *line)) return false;
    ++number_;
    if (!line->empty() && line->back() == '\r') line->pop_back();
    return true;
  }
  int number() const { return number_; }

 private:
  std::istream& in_;
  int number_ = 0;
};

bool to_size(const std::string& s, std::size_t* v) {
  const char* end = s.data() + s.size();
  const auto [p, ec] = std::from_chars(s.data(), end, *v);
  return ec == std::errc() && p == end && !s.empty();
}

// Numbers of the first `n` words of a line; false if there are fewer or one is not a number.
bool sizes(const std::string& line, std::size_t n, std::vector<std::size_t>* out) {
  const std::vector<std::string> words = text::split_whitespace(line);
  if (words.size() < n) return false;
  out->assign(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    if (!to_size(words[i], &(*out)[i])) return false;
  }
  return true;
}

void record(std::unordered_map<std::size_t, int>& lines, std::size_t tag, int line,
            const std::string& path, const char* what) {
  const auto [it, inserted] = lines.emplace(tag, line);
  if (!inserted) {
    throw InvalidInput({path, line, ""}, std::string(what) + " tag " + std::to_string(tag) +
                                             " is defined twice (first on line " +
                                             std::to_string(it->second) + ")");
  }
}

// The tag of each entry line of a section, `count` lines (MSH 2.x: every line is an entry).
bool scan_v2(LineReader& r, MshLines& out, bool nodes, const std::string& path) {
  std::string line;
  std::vector<std::size_t> v;
  if (!r.next(&line) || !sizes(line, 1, &v)) return false;
  for (std::size_t i = 0, n = v[0]; i < n; ++i) {
    if (!r.next(&line) || !sizes(line, 1, &v)) return false;
    record(nodes ? out.node : out.element, v[0], r.number(), path, nodes ? "node" : "element");
  }
  return true;
}

// MSH 4.1 $Nodes: per entity block "dim tag parametric count", then `count` tag lines, then
// `count` coordinate lines.
bool scan_v4_nodes(LineReader& r, MshLines& out, const std::string& path) {
  std::string line;
  std::vector<std::size_t> v;
  if (!r.next(&line) || !sizes(line, 2, &v)) return false;
  for (std::size_t b = 0, blocks = v[0]; b < blocks; ++b) {
    if (!r.next(&line) || !sizes(line, 4, &v)) return false;
    const std::size_t count = v[3];
    for (std::size_t i = 0; i < count; ++i) {
      if (!r.next(&line) || !sizes(line, 1, &v)) return false;
      record(out.node, v[0], r.number(), path, "node");
    }
    for (std::size_t i = 0; i < count; ++i) {
      if (!r.next(&line)) return false;
    }
  }
  return true;
}

// MSH 4.1 $Elements: per entity block "dim tag type count", then `count` lines "tag nodes...".
bool scan_v4_elements(LineReader& r, MshLines& out, const std::string& path) {
  std::string line;
  std::vector<std::size_t> v;
  if (!r.next(&line) || !sizes(line, 2, &v)) return false;
  for (std::size_t b = 0, blocks = v[0]; b < blocks; ++b) {
    if (!r.next(&line) || !sizes(line, 4, &v)) return false;
    for (std::size_t i = 0, count = v[3]; i < count; ++i) {
      if (!r.next(&line) || !sizes(line, 1, &v)) return false;
      record(out.element, v[0], r.number(), path, "element");
    }
  }
  return true;
}

}  // namespace

MshLines scan_msh_lines(const std::string& path) {
  MshLines out;
  std::ifstream in(path, std::ios::binary);
  if (!in) return out;
  LineReader r(in);
  std::string line;
  int major = 0;
  bool v41 = false;
  while (r.next(&line)) {
    const std::string t = text::trim(line);
    if (t == "$MeshFormat") {
      if (!r.next(&line)) return {};
      const std::vector<std::string> w = text::split_whitespace(line);
      if (w.size() < 2 || w[1] != "0") return {};  // binary (file-type 1) or damaged
      major = w[0].empty() ? 0 : w[0][0] - '0';
      v41 = w[0].rfind("4.1", 0) == 0;
      if (major != 2 && !v41) return {};
    } else if (t == "$Nodes" || t == "$Elements") {
      if (major == 0) return {};
      const bool nodes = t == "$Nodes";
      const bool ok = major == 2 ? scan_v2(r, out, nodes, path)
                      : nodes    ? scan_v4_nodes(r, out, path)
                                 : scan_v4_elements(r, out, path);
      if (!ok) return {};  // Gmsh reports what is wrong
    }
  }
  out.scanned = major != 0;
  return out;
}

}  // namespace stickslip
