// SUMO's floating car data (`sumo --fcd-output`): `<fcd-export><timestep time="t"><vehicle id x y
// angle type speed .../>...</timestep>...</fcd-export>`, read into trajectories
// (hv/traffic/trajectories.h).
//
// SUMO's x, y is the vehicle's FRONT BUMPER (sumo.dlr.de, "FCDOutput"), in the network's
// coordinates; the trajectories hold the centre: the position moved back by half the vehicle's
// length (its type's, hv::vehicleSizeOf) along its heading (angle: degrees clockwise from north, as
// the trajectories'). `<person>` and `<container>` elements are not vehicles and are skipped.
#pragma once

#include "hv/traffic/trajectories.h"
#include "hv/util/diagnostics.h"

#include <string>
#include <string_view>

namespace hv {

// Throws InputError naming the source, the line and the attribute for a broken file.
Trajectories parseSumoFcd(std::string_view xml, const std::string& source, Diagnostics& diag);
Trajectories readSumoFcd(const std::string& path, Diagnostics& diag);
// The CSV trajectories (hv::parseTrajectoriesCsv) of a file.
Trajectories readTrajectoriesCsv(const std::string& path, Diagnostics& diag);

}  // namespace hv
