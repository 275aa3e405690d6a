#pragma once
// Ray and hit files for `relief trace` and `relief rays`, in texel space. The format comes from
// the path: ".npy" is NumPy's (io/npy.h), anything else (and "-", stdin/stdout) is CSV.
// - Rays, CSV: one ray per line "ox,oy,oz,dx,dy,dz[,tmax]" (a header line is allowed; a line
//   without tmax has none). .npy: float32 or float64, shape (N, 6) or (N, 7) in the same order.
// - Hits, CSV: a header "hit,t,x,y,z,steps,fetches", then one line per ray; a miss is
//   "0,inf,nan,nan,nan,steps,fetches". .npy: a structured array of shape (N,) with the fields of
//   kHitFields (packed, 25 bytes a hit; a miss has t = inf and x, y, z = nan).
#include <relief/core/error.h>
#include <relief/core/math.h>
#include <relief/io/npy.h>

#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace relief {

// The largest --max-rays (28 bytes a ray in memory: 3.5 GiB) and its default.
inline constexpr size_t kMaxRaysPerFile = size_t(1) << 27;
inline constexpr size_t kDefaultMaxRays = size_t(1) << 24;
// A longer line is not a ray (seven numbers fit in a few hundred bytes); it ends the read early.
inline constexpr size_t kMaxRayLineBytes = 4096;

// Beyond this an origin cannot be brought to the box even in double precision (ulp 2^-12 texel
// here); such rays are refused rather than traced to a hit somewhere else.
inline constexpr double kMaxRayOrigin = double(int64_t(1) << 40);

// The dtype of a .npy hit file: np.dtype([('hit', '?'), ('t', '<f4'), ('x', '<f4'), ('y', '<f4'),
// ('z', '<f4'), ('steps', '<i4'), ('fetches', '<i4')]).
inline const NpyField kHitFields[] = {{"hit", "|b1"},    {"t", "<f4"}, {"x", "<f4"},
                                      {"y", "<f4"},      {"z", "<f4"}, {"steps", "<i4"},
                                      {"fetches", "<i4"}};

// The checks every ray source applies (ray files, the Python module's arrays) to
// ox,oy,oz,dx,dy,dz and, with count 7, tmax: finite numbers, the origin within kMaxRayOrigin, a
// usable direction (normalized unless already of unit length), tmax >= 0. The message names no
// location: the caller prefixes its own (file and line, array row).
Result<Ray> checkedRay(const double (&values)[7], int count);

// True when `path` names a .npy file (by its extension, in any case).
bool isNpyPath(const std::string& path);

// Directions are normalized (one already of unit length to float precision is kept bit for bit,
// so rays written by `relief rays` trace exactly as `render` traces them); zero or non-finite
// values, origins beyond kMaxRayOrigin, a negative or NaN tmax (+inf is none), a NUL byte, an
// overlong line and more than `maxRays` rays are errors naming the line (the row in .npy), found
// while reading (nothing is read past them). A ray's tmax is its Ray::tMax.
Result<std::vector<Ray>> parseRays(std::string_view text, const std::string& what,
                                   size_t maxRays = kDefaultMaxRays);
// The .npy ray reader on bytes in memory (the fuzz target's entry).
Result<std::vector<Ray>> decodeNpyRays(std::span<const unsigned char> bytes,
                                       const std::string& what, size_t maxRays = kDefaultMaxRays);
// `path` is a regular file (CSV or .npy) or "-" (CSV on stdin, read as it streams in).
Result<std::vector<Ray>> readRays(const std::string& path, size_t maxRays = kDefaultMaxRays);

// The file contents; tmax is written (7 columns) when a ray has a finite one.
std::string formatRays(const std::vector<Ray>& rays);
std::string npyRays(const std::vector<Ray>& rays);
Status writeRays(const std::string& path, const std::vector<Ray>& rays);

std::string formatHits(const std::vector<Hit>& hits);
std::string npyHits(const std::vector<Hit>& hits);
Status writeHits(const std::string& path, const std::vector<Hit>& hits);

}  // namespace relief
