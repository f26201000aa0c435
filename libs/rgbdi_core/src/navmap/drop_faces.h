// Drop faces: the top of a wall going down (a hole or a drop seen only a few centimetres down)
// told from floor by the spread of a cell's points (doc/navigation-maps.md "Layers and cell
// states", step 5).
#pragma once

#include <vector>

#include "rgbdi/navmap/nav_map.h"

namespace rgbdi::navmap::detail {

/// Drop faces (NavMapOptions::drop_face_min_rise_m): a free cell whose points rise at least
/// drop_face_min_rise_m above its lowest surface while that surface lies drop_face_min_depth_m
/// or more below its reference ground shows the top of a wall going down, not a floor: a step
/// edge, and so are its free neighbours standing drop_face_min_depth_m or more above it (the
/// rim). The camera sees a hole's far wall only a few centimetres down, less than max_step_m,
/// so without this the face joins the floor's plateau as free. A riser going up from the floor
/// has the floor as its lowest surface (not below the reference) and stays free.
/// `rise`: CellSurface::rise_m per cell; `reference`: each cell's reference ground (that under
/// its nearest path position). Changes free cells to step edges only.
void markDropFaces(NavMap& m, const std::vector<float>& rise, const std::vector<float>& reference,
                   const NavMapOptions& o);

}  // namespace rgbdi::navmap::detail
