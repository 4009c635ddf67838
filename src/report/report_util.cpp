// Helpers shared by the report's figure and page code.
#include <cmath>
#include <fstream>

#include <fmt/format.h>

#include "bridgefit/core/error.hpp"
#include "report_impl.hpp"

namespace bridgefit::report::detail {

Display DisplayOf(const std::string& name) {
  if (name == "sigma_c") return {"&sigma;<sub>c</sub> (peak bridging stress)", 1e-6, "MPa"};
  if (name == "delta_c") return {"&delta;<sub>c</sub> (critical opening)", 1e3, "mm"};
  if (name == "J_B") return {"J<sub>B</sub> (bridging toughness)", 1.0, "J/m<sup>2</sup>"};
  return {"J<sub>tip,c</sub> (crack-tip toughness)", 1.0, "J/m<sup>2</sup>"};
}

std::string GnuplotUnit(const std::string& name) {
  if (name == "sigma_c") return "MPa";
  if (name == "delta_c") return "mm";
  return "J/m^2";
}

std::string GnuplotSymbol(const std::string& name) {
  if (name == "sigma_c") return "{/Symbol s}_c";
  if (name == "delta_c") return "{/Symbol d}_c";
  if (name == "J_B") return "J_B";
  return "J_{tip,c}";
}

std::string Num(double v, double factor) {
  if (!std::isfinite(v)) return "&ndash;";
  return fmt::format("{:.4g}", v * factor);
}

std::string Escape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '&': out += "&amp;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string GnuplotText(const std::string& text) {
  std::string out;
  for (char c : text) out += c == '\'' ? std::string("''") : std::string(1, c);
  return out;
}

void WriteFile(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) throw Error(ErrorKind::kRuntime, "cannot write file", {.file = path.string()});
}

const char* const kTerminal =
    "set terminal pngcairo size 860,520 enhanced font 'Sans,11'\n"
    "set size 1,1\nset origin 0,0\nunset tmargin\nunset bmargin\nunset lmargin\nunset rmargin\n"
    "set format x '%g'\nset format y '%g'\nunset logscale\nset autoscale\nunset title\n"
    "unset label\nunset arrow\nunset object\nset xtics norotate font ''\nset ytics in\n"
    "unset x2tics\nunset x2label\nset xtics mirror\nset key top left\nset size noratio\n"
    "set yrange [*:*] noreverse\nset xrange [*:*]\n";

// Screen margins (fractions of the 860 x 520 canvas): the upper panel ends at
// 0.42 and the lower begins at 0.36, 31 px apart, more than one tick label
// (11 pt, about 15 px) half above and half below the panels' facing edges.
// The lower panel takes the upper one's x range (same crack length or
// displacement at the same place), so the upper panel must be plotted first.
const char* const kUpperPanel =
    "set lmargin at screen 0.11\nset rmargin at screen 0.97\n"
    "set tmargin at screen 0.90\nset bmargin at screen 0.42\nset format x ''\nunset xlabel\n";
const char* const kLowerPanel =
    "set lmargin at screen 0.11\nset rmargin at screen 0.97\n"
    "set tmargin at screen 0.36\nset bmargin at screen 0.11\nset format x '%g'\nunset title\n"
    "set ytics out scale 0.5\nset ytics autofreq\nunset key\n"
    "set xrange [GPVAL_X_MIN:GPVAL_X_MAX]\n";  // the upper panel's x axis, whatever each panel holds

}  // namespace bridgefit::report::detail
