// The [sim] lines of simulation.ini for settings that are off or neutral by default (world
// variation, exposure drift, IMU errors and separate streams, depth artefacts, stamp jitter):
// each is written only when it differs from its default, so that a default sequence's
// simulation.ini is the one of versions without these settings.
#pragma once

#include <ostream>

#include "rgbdi/sim/sequence.h"

namespace rgbdi::sim {

void writeOptionalSimSettings(std::ostream& os, const SimOptions& o);

}  // namespace rgbdi::sim
