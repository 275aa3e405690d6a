#pragma once
// Ray files for `relief trace`: one ray per line "ox,oy,oz,dx,dy,dz" in texel space (a header
// line is allowed); hit files: one line per ray "hit,t,x,y,z,steps".
#include <relief/core/error.h>
#include <relief/core/math.h>

#include <string>
#include <string_view>
#include <vector>

namespace relief {

inline constexpr size_t kMaxRaysPerFile = size_t(1) << 27;

// Directions are normalized; zero or non-finite values are errors naming the line.
Result<std::vector<Ray>> parseRays(std::string_view text, const std::string& what);
Result<std::vector<Ray>> readRays(const std::string& path);

std::string formatHits(const std::vector<Hit>& hits);
Status writeHits(const std::string& path, const std::vector<Hit>& hits);

}  // namespace relief
