// The painters of each texture style (one file each) and the pieces they share.
// All sizes are chosen in metres and converted with `tpm` (texels per metre), so a different
// texel size gives the same world-scale look.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "sim/render/det_random.h"
#include "sim/render/wrap_painter.h"

namespace rgbdi::sim::detail {

void paintPosters(WrapPainter& p, DetRandom& r, double tpm);
void paintBricks(WrapPainter& p, DetRandom& r, double tpm);
void paintTiles(WrapPainter& p, DetRandom& r, double tpm);
void paintShelves(WrapPainter& p, DetRandom& r, double tpm);
void paintSpeckle(WrapPainter& p, DetRandom& r, double tpm);
void paintPlanks(WrapPainter& p, DetRandom& r, double tpm);

/// Lines of "words" (small blocks) filling the rectangle, like printed text seen from afar.
void paintText(WrapPainter& p, DetRandom& r, double x, double y, double w, double h,
               double line_height, const cv::Scalar& color);
/// A poster/sign: background, optional border, a few bold shapes and some text.
void paintPoster(WrapPainter& p, DetRandom& r, double x, double y, double w, double h, double tpm);

/// Splits [0, total) into consecutive lengths drawn uniformly in [lo, hi]; the last piece
/// absorbs the remainder so the pieces tile the period exactly (pieces shorter than lo/2 merge
/// with their neighbour).
std::vector<double> splitPeriod(DetRandom& r, double total, double lo, double hi);

}  // namespace rgbdi::sim::detail
