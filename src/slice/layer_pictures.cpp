#include "frep/slice/layer_pictures.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

#include "frep/error.hpp"

namespace frep::slice {
namespace {

const unsigned char* colour_of(PathRole r) {
  switch (r) {
    case PathRole::WallOuter: return LayerColours::wall_outer;
    case PathRole::WallInner: return LayerColours::wall_inner;
    case PathRole::Skin: return LayerColours::skin;
    default: return LayerColours::fill;
  }
}

std::string hex(const unsigned char* c) {
  char b[8];
  std::snprintf(b, sizeof b, "#%02x%02x%02x", c[0], c[1], c[2]);
  return b;
}

}  // namespace

void write_layers_svg(std::ostream& out, const SlicedPart& part, const PrintSettings& s, int shown, int first, int last) {
  if (last < 0) last = static_cast<int>(part.layers.size()) - 1;
  const double pad = 2;
  const double x0 = part.lo.x - pad, y0 = part.lo.y - pad;
  const double wd = part.hi.x - part.lo.x + 2 * pad, ht = part.hi.y - part.lo.y + 2 * pad;
  char b[512];
  // y grows up on the bed and down in SVG: flip with a transform.
  std::snprintf(b, sizeof b,
                "<svg xmlns=\"http://www.w3.org/2000/svg\" xmlns:inkscape=\"http://www.inkscape.org/namespaces/inkscape\" "
                "width=\"%.3fmm\" height=\"%.3fmm\" viewBox=\"%.4f %.4f %.4f %.4f\">\n",
                wd, ht, x0, -(y0 + ht), wd, ht);
  out << b;
  out << "<!-- frep slice: one group per layer; walls " << hex(LayerColours::wall_outer) << " (outer) and "
      << hex(LayerColours::wall_inner) << ", skin " << hex(LayerColours::skin) << ", infill " << hex(LayerColours::fill)
      << ", cross-section grey -->\n";
  for (const LayerPlan& l : part.layers) {
    if (l.index < first || l.index > last) continue;
    std::snprintf(b, sizeof b,
                  "<g id=\"layer-%d\" inkscape:groupmode=\"layer\" inkscape:label=\"layer %d z=%.4f\" "
                  "transform=\"scale(1,-1)\"%s>\n",
                  l.index, l.index, l.z, l.index == shown ? "" : " style=\"display:none\"");
    out << b;
    out << "<path fill=\"" << hex(LayerColours::outline) << "\" fill-rule=\"nonzero\" d=\"";
    for (const Ring& r : l.outline) {
      for (std::size_t k = 0; k < r.size(); ++k) {
        std::snprintf(b, sizeof b, "%s%.4f %.4f", k == 0 ? "M" : " L", r[k].x, r[k].y);
        out << b;
      }
      out << " Z";
    }
    out << "\"/>\n";
    for (const ToolPath& p : l.paths) {
      std::snprintf(b, sizeof b, "<path fill=\"none\" stroke=\"%s\" stroke-width=\"%.4f\" stroke-linecap=\"round\" "
                    "stroke-linejoin=\"round\" stroke-opacity=\"0.85\" d=\"", hex(colour_of(p.role)).c_str(), s.line_width);
      out << b;
      for (std::size_t k = 0; k < p.points.size(); ++k) {
        std::snprintf(b, sizeof b, "%s%.4f %.4f", k == 0 ? "M" : " L", p.points[k].x, p.points[k].y);
        out << b;
      }
      if (p.closed) out << " Z";
      out << "\"/>\n";
    }
    out << "</g>\n";
  }
  out << "</svg>\n";
}

Image layer_preview(const SlicedPart& part, const PrintSettings& s, int index, int pixels) {
  if (index < 0 || index >= static_cast<int>(part.layers.size()))
    throw InputError("", 0, "layer " + std::to_string(index) + " does not exist: the part has " +
                                std::to_string(part.layers.size()) + " layers (0 to " +
                                std::to_string(static_cast<int>(part.layers.size()) - 1) + ")");
  if (pixels < 16 || pixels > 16384) throw InputError("", 0, "the preview must be 16 to 16384 pixels wide");
  const LayerPlan& l = part.layers[static_cast<std::size_t>(index)];
  const double pad = 1;
  const double x0 = part.lo.x - pad, y0 = part.lo.y - pad;
  const double wd = part.hi.x - part.lo.x + 2 * pad, ht = part.hi.y - part.lo.y + 2 * pad;
  const double scale = pixels / std::max(wd, ht);  // pixels per mm: the longer side is `pixels`
  Image img;
  img.width = std::max(1, static_cast<int>(std::lround(wd * scale)));
  img.height = std::max(1, static_cast<int>(std::lround(ht * scale)));
  img.channels = 3;
  img.pixels.assign(static_cast<std::size_t>(img.width) * static_cast<std::size_t>(img.height) * 3, 255);
  auto put = [&](int x, int y, const unsigned char* c) {
    unsigned char* p = &img.pixels[(static_cast<std::size_t>(y) * static_cast<std::size_t>(img.width) + static_cast<std::size_t>(x)) * 3];
    p[0] = c[0], p[1] = c[1], p[2] = c[2];
  };
  // The cross-section: nonzero winding along each row's centre.
  for (int y = 0; y < img.height; ++y) {
    const double my = y0 + ht - (y + 0.5) / scale;
    std::vector<std::pair<double, int>> hits;
    for (const Ring& r : l.outline)
      for (std::size_t k = 0, j = r.size() - 1; k < r.size(); j = k++) {
        const Point2 a = r[j], b = r[k];
        if ((a.y <= my) == (b.y <= my)) continue;
        hits.push_back({a.x + (my - a.y) / (b.y - a.y) * (b.x - a.x), b.y > a.y ? 1 : -1});
      }
    std::sort(hits.begin(), hits.end());
    int wind = 0;
    for (std::size_t k = 0; k + 1 < hits.size(); ++k) {
      wind += hits[k].second;
      if (wind == 0) continue;
      const int xa = std::max(0, static_cast<int>(std::ceil((hits[k].first - x0) * scale - 0.5)));
      const int xb = std::min(img.width - 1, static_cast<int>(std::floor((hits[k + 1].first - x0) * scale - 0.5)));
      for (int x = xa; x <= xb; ++x) put(x, y, LayerColours::outline);
    }
  }
  // Lines at their width.
  const double r = s.line_width / 2 * scale;
  for (const ToolPath& p : l.paths) {
    const std::size_t n = p.points.size();
    for (std::size_t k = 0; k + 1 < n + (p.closed ? 1 : 0); ++k) {
      const Point2 a{(p.points[k].x - x0) * scale, (y0 + ht - p.points[k].y) * scale};
      const Point2& q = p.points[(k + 1) % n];
      const Point2 b{(q.x - x0) * scale, (y0 + ht - q.y) * scale};
      const int xa = std::max(0, static_cast<int>(std::floor(std::min(a.x, b.x) - r)));
      const int xb = std::min(img.width - 1, static_cast<int>(std::ceil(std::max(a.x, b.x) + r)));
      const int ya = std::max(0, static_cast<int>(std::floor(std::min(a.y, b.y) - r)));
      const int yb = std::min(img.height - 1, static_cast<int>(std::ceil(std::max(a.y, b.y) + r)));
      const double dx = b.x - a.x, dy = b.y - a.y, len2 = dx * dx + dy * dy;
      for (int y = ya; y <= yb; ++y)
        for (int x = xa; x <= xb; ++x) {
          const double px = x + 0.5 - a.x, py = y + 0.5 - a.y;
          const double t = len2 > 0 ? std::clamp((px * dx + py * dy) / len2, 0.0, 1.0) : 0;
          const double ex = px - t * dx, ey = py - t * dy;
          if (ex * ex + ey * ey <= r * r) put(x, y, colour_of(p.role));
        }
    }
  }
  return img;
}

}  // namespace frep::slice
