// Tests of the 2D quality report (voroclip/mesh.h): closed-form angles and radius ratios,
// histogram totals, the JSON keys and values, the SVG bar chart.
#include <catch2/catch.hpp>

#include <cmath>
#include <nlohmann/json.hpp>
#include <numeric>
#include <sstream>
#include <string>

#include "voroclip/mesh.h"

using voroclip::Mesh2;
using voroclip::TriangleQuality2;

namespace {

std::uint32_t total(const std::vector<std::uint32_t>& h) {
  return std::accumulate(h.begin(), h.end(), 0u);
}

}  // namespace

TEST_CASE("quality2d: closed forms", "[mesh]") {
  Mesh2 m;
  // An equilateral triangle and a right isosceles one (counter-clockwise).
  m.xy = {0, 0, 2, 0, 1, std::sqrt(3.0), 3, 0, 4, 0, 3, 1};
  m.triangles = {0, 1, 2, 3, 4, 5};
  const TriangleQuality2 q = voroclip::triangle_quality2(m, 5.0);
  CHECK(q.nb_triangles == 2);
  CHECK(q.nb_vertices == 6);
  CHECK(q.min_angle == Approx(45).epsilon(1e-12));
  CHECK(q.max_angle == Approx(90).epsilon(1e-12));
  CHECK(q.mean_angle == Approx(60).epsilon(1e-12));
  CHECK(q.mean_min_angle == Approx((60 + 45) / 2.0).epsilon(1e-12));
  CHECK(q.mean_max_angle == Approx((60 + 90) / 2.0).epsilon(1e-12));
  // 2 r / R: 1 for the equilateral triangle, 2 (sqrt(2) - 1) for the right isosceles one.
  const double right = 2 * (std::sqrt(2.0) - 1);
  CHECK(q.min_radius_ratio == Approx(right).epsilon(1e-12));
  CHECK(q.mean_radius_ratio == Approx((1 + right) / 2).epsilon(1e-12));
  CHECK(q.nb_below_30 == 0);
  REQUIRE(q.angle_histogram.size() == 36);
  CHECK(total(q.angle_histogram) == 6);
  CHECK(total(q.min_angle_histogram) == 2);
  CHECK(total(q.max_angle_histogram) == 2);
  CHECK(q.max_angle_histogram[18] == 1);                      // 90 degrees in [90, 95)
  CHECK(q.min_angle_histogram[9] == 1);                       // 45 in [45, 50)
  CHECK(q.angle_histogram[12] + q.angle_histogram[11] == 3);  // the three 60s (rounding)

  CHECK_THROWS_AS(voroclip::triangle_quality2(m, 0), voroclip::Error);
  const TriangleQuality2 empty = voroclip::triangle_quality2(Mesh2{});
  CHECK(empty.nb_triangles == 0);
  CHECK(voroclip::quality_text(empty).find("0 triangles") != std::string::npos);
}

TEST_CASE("quality2d: a needle counts below 30 degrees", "[mesh]") {
  Mesh2 m;
  m.xy = {0, 0, 10, 0, 5, 1};
  m.triangles = {0, 1, 2};
  const TriangleQuality2 q = voroclip::triangle_quality2(m);
  const double small = std::atan2(1.0, 5.0) * 180 / M_PI;
  CHECK(q.min_angle == Approx(small).epsilon(1e-12));
  CHECK(q.max_angle == Approx(180 - 2 * small).epsilon(1e-12));
  CHECK(q.nb_below_30 == 1);
}

TEST_CASE("quality2d: JSON and SVG", "[mesh]") {
  Mesh2 m;
  m.xy = {0, 0, 2, 0, 1, std::sqrt(3.0), 3, 0, 4, 0, 3, 1};
  m.triangles = {0, 1, 2, 3, 4, 5};
  const TriangleQuality2 q = voroclip::triangle_quality2(m);
  const nlohmann::json j = nlohmann::json::parse(voroclip::quality_json(q));
  CHECK(j["nb_triangles"] == 2);
  CHECK(j["min_angle_deg"].get<double>() == q.min_angle);
  CHECK(j["mean_min_angle_deg"].get<double>() == q.mean_min_angle);
  CHECK(j["max_angle_deg"].get<double>() == q.max_angle);
  CHECK(j["mean_radius_ratio"].get<double>() == q.mean_radius_ratio);
  CHECK(j["angle_histogram"].size() == q.angle_histogram.size());
  CHECK(j["min_angle_histogram"][22].get<int>() == 1);  // 45 degrees, bins of 2

  std::ostringstream svg;
  voroclip::write_quality_svg(svg, q, "a <test> & \"title\"");
  const std::string s = svg.str();
  CHECK(s.rfind("<svg", 0) == 0);
  CHECK(s.find("</svg>") != std::string::npos);
  CHECK(s.find("a &lt;test&gt; &amp; &quot;title&quot;") != std::string::npos);
  CHECK(s.find("<test>") == std::string::npos);
}
