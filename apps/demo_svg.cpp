// SVG picture of the classroom example: one panel per evaluation (naive | exact), point
// (i, j) drawn as a 1 x 1 cell with i growing to the right and j upwards. Each row is
// run-length encoded and all cells of one sign in a panel form a single <path>, which keeps
// the file small. Every number written is an integer, so the output is locale-independent
// and byte-for-byte deterministic. Text is ASCII with XML character references.
#include <array>
#include <ostream>
#include <string>

#include "demo.h"

namespace voroclip::cli {
namespace {

constexpr int kScale = 2;
constexpr int kGrid = static_cast<int>(ClassroomResult::kGrid);
constexpr int kPanel = kGrid * kScale;
constexpr int kMargin = 40;
constexpr int kGap = 60;
constexpr int kPanelTop = 110;
constexpr int kWidth = 2 * kMargin + 2 * kPanel + kGap;
constexpr int kHeight = kPanelTop + kPanel + 90;

struct SignStyle {
  Sign sign;
  const char* colour;
  const char* label;
};

constexpr std::array<SignStyle, 3> kStyles = {{
    {Sign::positive, "#4575b4", "positive: p, q, r counter-clockwise"},
    {Sign::zero, "#ffd92f", "zero: p on the line through q and r"},
    {Sign::negative, "#d73027", "negative: clockwise"},
}};

std::string num(int x) { return std::to_string(x); }

// The cells of sign `s`, as one path in grid units (row j at y = kGrid - 1 - j).
std::string cells_path(const std::vector<Sign>& signs, Sign s) {
  std::string d;
  for (int j = 0; j < kGrid; ++j) {
    const Sign* row = signs.data() + static_cast<std::size_t>(j) * ClassroomResult::kGrid;
    const std::string y = num(kGrid - 1 - j);
    int i = 0;
    while (i < kGrid) {
      if (row[i] != s) {
        ++i;
        continue;
      }
      const int begin = i;
      while (i < kGrid && row[i] == s) ++i;
      const std::string len = num(i - begin);
      d += "M" + num(begin) + " " + y + "h" + len + "v1h-" + len + "z";
    }
  }
  return d;
}

void write_panel(std::ostream& out, const std::vector<Sign>& signs, int x, const char* title,
                 const std::string& subtitle) {
  const int centre = x + kPanel / 2;
  out << "<text x=\"" << num(centre) << "\" y=\"" << num(kPanelTop - 28)
      << "\" text-anchor=\"middle\" font-size=\"16\" font-weight=\"bold\">" << title << "</text>\n";
  out << "<text x=\"" << num(centre) << "\" y=\"" << num(kPanelTop - 10)
      << "\" text-anchor=\"middle\" font-size=\"13\">" << subtitle << "</text>\n";
  out << "<g transform=\"translate(" << num(x) << "," << num(kPanelTop) << ") scale(" << num(kScale)
      << ")\" shape-rendering=\"crispEdges\">\n";
  for (const SignStyle& style : kStyles) {
    const std::string d = cells_path(signs, style.sign);
    if (!d.empty()) out << "<path fill=\"" << style.colour << "\" d=\"" << d << "\"/>\n";
  }
  out << "</g>\n";
  out << "<rect x=\"" << num(x) << "\" y=\"" << num(kPanelTop) << "\" width=\"" << num(kPanel)
      << "\" height=\"" << num(kPanel) << "\" fill=\"none\" stroke=\"#333333\"/>\n";
  out << "<text x=\"" << num(centre) << "\" y=\"" << num(kPanelTop + kPanel + 20)
      << "\" text-anchor=\"middle\" font-size=\"13\">i = 0 &#8230; 255 &#8594;</text>\n";
  const int label_x = x - 10;
  const int label_y = kPanelTop + kPanel / 2;
  out << "<text x=\"" << num(label_x) << "\" y=\"" << num(label_y)
      << "\" text-anchor=\"middle\" font-size=\"13\" transform=\"rotate(-90 " << num(label_x) << " "
      << num(label_y) << ")\">j = 0 &#8230; 255 &#8594;</text>\n";
}

}  // namespace

void write_classroom_svg(const ClassroomResult& result, std::ostream& out) {
  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << num(kWidth) << "\" height=\""
      << num(kHeight) << "\" viewBox=\"0 0 " << num(kWidth) << " " << num(kHeight)
      << "\" font-family=\"DejaVu Sans, Helvetica, Arial, sans-serif\">\n"
      << "<title>voroclip demo: the classroom example of Kettner et al. (CGTA 2008)</title>\n"
      << "<rect width=\"100%\" height=\"100%\" fill=\"#ffffff\"/>\n";
  out << "<text x=\"" << num(kWidth / 2) << "\" y=\"30\" text-anchor=\"middle\" font-size=\"18\""
      << " font-weight=\"bold\">Sign of orient2d(p, q, r), q = (12, 12), r = (24, 24)</text>\n";
  out << "<text x=\"" << num(kWidth / 2) << "\" y=\"52\" text-anchor=\"middle\" font-size=\"13\">"
      << "p = (0.5 + i&#183;u, 0.5 + j&#183;u), u = 2<tspan baseline-shift=\"super\" "
      << "font-size=\"9\">&#8722;53</tspan>, 0 &#8804; i, j &lt; 256: the classroom example "
      << "of Kettner, Mehlhorn, Pion, Schirra and Yap (CGTA 2008)</text>\n";

  const std::size_t points = result.exact.size();
  write_panel(
      out, result.naive, kMargin, "Naive floating point (orient2d_fast)",
      std::to_string(result.naive_wrong) + " of " + std::to_string(points) + " signs wrong");
  write_panel(out, result.exact, kMargin + kPanel + kGap, "Exact (voroclip::orient2d)",
              std::to_string(result.exact_counts.zero) + " zero, exactly on the diagonal i = j");

  int x = kMargin;
  const int y = kPanelTop + kPanel + 50;
  for (const SignStyle& style : kStyles) {
    out << "<rect x=\"" << num(x) << "\" y=\"" << num(y - 12) << "\" width=\"14\" height=\"14\""
        << " fill=\"" << style.colour << "\" stroke=\"#333333\"/>\n"
        << "<text x=\"" << num(x + 20) << "\" y=\"" << num(y) << "\" font-size=\"13\">"
        << style.label << "</text>\n";
    x += 300;
  }
  out << "</svg>\n";
}

}  // namespace voroclip::cli
