// Timing of a rolling-shutter image: every row is exposed at its own time.
//
// The rows are read one after another in `readout_s` (the time from the first row to the row
// after the last; row pitch readout_s / rows); the image is stamped at the reference row. Row
// coordinate y (pixel centres at integers, may be fractional for a sub-pixel feature) is exposed
// at
//   t(y) = t_ref + s * (y - y_ref) * readout_s / rows
// with s = +1 when the rows are read top to bottom, -1 bottom to top, and y_ref the reference
// row: the middle (rows - 1) / 2 (the VINS-Mono convention, so stamps sit at the image's mean
// exposure time), or the first row read (0 top to bottom, rows - 1 bottom to top).
// readout_s = 0 is a global shutter: every row at t_ref.
#pragma once

namespace rgbdi {

struct RollingShutter {
  double readout_s = 0.0;        ///< [s] 0 = global shutter
  int rows = 0;                  ///< [px] image height
  bool bottom_to_top = false;    ///< read direction (false: top row first)
  bool reference_middle = true;  ///< stamp at the middle row (true) or the first row read

  bool global() const { return readout_s == 0.0; }
  /// [px] the reference row y_ref.
  double referenceRow() const {
    if (reference_middle) return 0.5 * (rows - 1);
    return bottom_to_top ? rows - 1.0 : 0.0;
  }
  /// [unitless] (t(y) - t_ref) / readout_s for row coordinate y (its share of the readout, -0.5 to
  /// 0.5 with the middle reference row); defined for any readout, also 0, as long as rows > 0.
  double rowFraction(double y) const {
    if (rows <= 0) return 0.0;
    const double s = bottom_to_top ? -1.0 : 1.0;
    return s * (y - referenceRow()) / rows;
  }
  /// [s] t(y) - t_ref for row coordinate y.
  double rowTime(double y) const {
    if (readout_s == 0.0 || rows <= 0) return 0.0;
    const double s = bottom_to_top ? -1.0 : 1.0;
    return s * (y - referenceRow()) * readout_s / rows;
  }
};

}  // namespace rgbdi
