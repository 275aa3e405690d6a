#pragma once
// Ray files for `relief trace`: one ray per line "ox,oy,oz,dx,dy,dz" in texel space (a header
// line is allowed); hit files: one line per ray "hit,t,x,y,z,steps".
#include <relief/core/error.h>
#include <relief/core/math.h>

#include <string>
#include <string_view>
#include <vector>

namespace relief {

// The largest --max-rays (28 bytes a ray in memory: 3.5 GiB) and its default.
inline constexpr size_t kMaxRaysPerFile = size_t(1) << 27;
inline constexpr size_t kDefaultMaxRays = size_t(1) << 24;
// A longer line is not a ray (six numbers fit in a few hundred bytes); it ends the read early.
inline constexpr size_t kMaxRayLineBytes = 4096;

// Beyond this an origin cannot be brought to the box even in double precision (ulp 2^-12 texel
// here); such rays are refused rather than traced to a hit somewhere else.
inline constexpr double kMaxRayOrigin = double(int64_t(1) << 40);

// The checks every ray source applies (ray files, the Python module's arrays): finite numbers
// ox,oy,oz,dx,dy,dz, the origin within kMaxRayOrigin, a usable direction (normalized here). The
// message names no location: the caller prefixes its own (file and line, array row).
Result<Ray> checkedRay(const float (&values)[6]);

// Directions are normalized; zero or non-finite values, origins beyond kMaxRayOrigin, a NUL byte,
// an overlong line and more than `maxRays` rays are errors naming the line, found while reading
// (nothing is read past them).
Result<std::vector<Ray>> parseRays(std::string_view text, const std::string& what,
                                   size_t maxRays = kDefaultMaxRays);
// `path` is a regular file or "-" (stdin).
Result<std::vector<Ray>> readRays(const std::string& path, size_t maxRays = kDefaultMaxRays);

std::string formatHits(const std::vector<Hit>& hits);
Status writeHits(const std::string& path, const std::vector<Hit>& hits);

}  // namespace relief
