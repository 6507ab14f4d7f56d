#include <fmt/core.h>

#include <cstdio>
#include <cstdlib>
#include <iostream>

#include "commands.hpp"
#include "frep/error.hpp"
#include "frep/eval/evaluators.hpp"
#include "frep/io/atomic_file.hpp"
#include "frep/io/load.hpp"

namespace frep::cli {
namespace {

struct Points {
  std::vector<float> x, y, z;
};

// One point per line: `x y [z]`, separated by spaces, tabs or commas; `#` starts a comment.
Points parse_points(const std::string& text, const std::string& name) {
  Points p;
  std::size_t pos = 0;
  std::uint64_t line_no = 0;
  while (pos < text.size()) {
    std::size_t eol = text.find('\n', pos);
    if (eol == std::string::npos) eol = text.size();
    std::string line = text.substr(pos, eol - pos);
    pos = eol + 1;
    ++line_no;
    if (auto h = line.find('#'); h != std::string::npos) line.resize(h);
    for (char& c : line)
      if (c == ',' || c == '\t' || c == '\r') c = ' ';
    float v[4];
    int n = 0;
    const char* s = line.c_str();
    while (true) {
      while (*s == ' ') ++s;
      if (!*s) break;
      if (n == 3) throw InputError(name, line_no, "expected 2 or 3 numbers per line, got more");
      char* end = nullptr;
      v[n] = std::strtof(s, &end);
      if (end == s || (*end != ' ' && *end != '\0'))
        throw InputError(name, line_no, "bad number '" + std::string(s, std::strcspn(s, " ")) + "'");
      ++n;
      s = end;
    }
    if (n == 0) continue;
    if (n == 1) throw InputError(name, line_no, "expected 2 or 3 numbers per line, got 1");
    p.x.push_back(v[0]);
    p.y.push_back(v[1]);
    p.z.push_back(n == 3 ? v[2] : 0.0f);
  }
  return p;
}

}  // namespace

void register_eval(CLI::App& app) {
  auto* cmd = app.add_subcommand("eval", "Evaluate an expression at points, one value per line (%.9g)");
  struct Args {
    std::string file, points;
    bool grad = false;
  };
  auto a = std::make_shared<Args>();
  cmd->add_option("FILE", a->file, "Expression file (.vm)")->required();
  cmd->add_option("--points,-p", a->points,
                  "Points file, one 'x y z' per line (commas allowed; 'x y' means z = 0); - for stdin")
      ->required();
  cmd->add_flag("--grad,-g", a->grad, "Also print d/dx d/dy d/dz after each value");
  cmd->callback([a] {
    const Model m = load_expression(a->file);
    std::string text;
    if (a->points == "-") {
      text.assign(std::istreambuf_iterator<char>(std::cin), std::istreambuf_iterator<char>());
    } else {
      text = read_file(a->points);
    }
    const Points p = parse_points(text, a->points == "-" ? "<stdin>" : a->points);
    const Tape tape = Tape::compile(*m.graph, m.root);
    const std::size_t n = p.x.size();
    std::string out;
    char buf[160];
    if (a->grad) {
      std::vector<Grad> g(n);
      GradEvaluator ev;
      ev.eval(tape, p.x.data(), p.y.data(), p.z.data(), g.data(), n);
      for (const Grad& r : g) {
        std::snprintf(buf, sizeof buf, "%.9g %.9g %.9g %.9g\n", r.v, r.dx, r.dy, r.dz);
        out += buf;
      }
    } else {
      std::vector<float> v(n);
      BatchEvaluator ev;
      ev.eval(tape, p.x.data(), p.y.data(), p.z.data(), v.data(), n);
      for (float r : v) {
        std::snprintf(buf, sizeof buf, "%.9g\n", r);
        out += buf;
      }
    }
    std::fwrite(out.data(), 1, out.size(), stdout);
  });
}

}  // namespace frep::cli
