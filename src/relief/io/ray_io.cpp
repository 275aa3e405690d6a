#include <fmt/format.h>
#include <relief/io/image_write.h>
#include <relief/io/ray_io.h>
#include <relief/io/read_common.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace relief {

namespace {

// Parses six or seven comma-separated numbers into v; the count, or 0 if the line has another
// shape.
int parseNumbers(std::string_view line, double (&v)[7]) {
    std::string copy(line);
    const char* p = copy.c_str();
    for (int k = 0; k < 7; ++k) {
        char* end = nullptr;
        v[k] = std::strtof(p, &end);  // float, as the rays are: "1e39" is inf here, refused
        if (end == p) return 0;
        p = end;
        while (*p == ' ' || *p == '\t' || *p == '\r') ++p;
        if (*p == '\0') return k + 1 >= 6 ? k + 1 : 0;
        if (*p != ',') return 0;
        ++p;
    }
    return 0;
}

bool isBlank(std::string_view line) {
    return line.find_first_not_of(" \t\r") == std::string_view::npos;
}

}  // namespace

Result<Ray> checkedRay(const double (&v)[7], int count) {
    for (int k = 0; k < 6; ++k)
        if (!std::isfinite(v[k])) return makeError(ErrorKind::InvalidInput, "non-finite value in ray");
    for (int k = 0; k < 3; ++k)
        if (std::abs(v[k]) > kMaxRayOrigin)
            return makeError(ErrorKind::InvalidInput,
                             "origin coordinate {:g} is too far for float precision "
                             "(at most {:g} texels from the origin)",
                             v[k], kMaxRayOrigin);
    const float tMax = count == 7 ? float(v[6]) : kInfinity;
    if (!(tMax >= 0.0f))
        return makeError(ErrorKind::InvalidInput, "tmax {} is not a number >= 0 (inf: none)", v[6]);
    vec3 d{float(v[3]), float(v[4]), float(v[5])};
    const float length = glm::length(d);
    if (!(length > 0.0f) || !std::isfinite(length))
        return makeError(ErrorKind::InvalidInput, "zero or unusable direction");
    // A unit direction to float precision is kept as it is: renormalizing moves it by an ulp.
    if (std::abs(length - 1.0f) > 4.0f * FLT_EPSILON) d /= length;
    return Ray{vec3(float(v[0]), float(v[1]), float(v[2])), d, tMax};
}

namespace {

// Rays one at a time, so that a limit stops the read where it is reached.
class RayCollector {
  public:
    RayCollector(const std::string& what, size_t maxRays) : m_what(what), m_maxRays(maxRays) {}

    Status add(const double (&v)[7], int count, const std::string& where) {
        auto ray = checkedRay(v, count);
        if (!ray) return makeError(ray.error().kind, "{}: {}", where, ray.error().message);
        if (m_rays.size() >= m_maxRays)
            return makeError(ErrorKind::InvalidInput, "{}: more than {} rays (--max-rays)", where,
                             m_maxRays);
        m_rays.push_back(*ray);
        return {};
    }

    // One CSV line.
    Status line(std::string_view line) {
        ++m_lineNumber;
        const auto where = [&] { return fmt::format("{}:{}", m_what, m_lineNumber); };
        if (line.find('\0') != std::string_view::npos)
            return makeError(ErrorKind::InvalidInput,
                             "{}: NUL byte in a ray line (not a text file?)", where());
        if (line.size() > kMaxRayLineBytes)
            return makeError(ErrorKind::InvalidInput, "{}: line longer than {} bytes", where(),
                             kMaxRayLineBytes);
        if (isBlank(line)) return {};
        double v[7];
        const int count = parseNumbers(line, v);
        if (count == 0) {
            const bool header =
                m_lineNumber == 1 && line.find_first_of("0123456789") == std::string_view::npos;
            if (header) return {};
            return makeError(ErrorKind::InvalidInput,
                             "{}: expected six numbers ox,oy,oz,dx,dy,dz (and optionally tmax)",
                             where());
        }
        return add(v, count, where());
    }
    std::vector<Ray> take() { return std::move(m_rays); }

  private:
    const std::string& m_what;
    size_t m_maxRays;
    size_t m_lineNumber = 0;
    std::vector<Ray> m_rays;
};

Result<std::vector<Ray>> readCsvRays(std::FILE* in, const std::string& what, size_t maxRays) {
    RayCollector parser(what, maxRays);
    // Lines are read in pieces of at most one overlong line, so no input grows memory unbounded;
    // a pipe is read as it streams in (fread waits for more or for its end).
    std::string line;
    char buffer[1024];
    for (;;) {
        const size_t n = std::fread(buffer, 1, sizeof buffer, in);
        for (size_t k = 0; k < n; ++k) {
            if (buffer[k] != '\n') {
                if (line.size() <= kMaxRayLineBytes)
                    line.push_back(buffer[k]);
                else if (Status s = parser.line(line); !s)
                    return s.error();
                continue;
            }
            if (Status s = parser.line(line); !s) return s.error();
            line.clear();
        }
        if (n < sizeof buffer) break;
    }
    if (std::ferror(in))
        return makeError(ErrorKind::Io, "{}: read failed: {}", what, std::strerror(errno));
    if (!line.empty())
        if (Status s = parser.line(line); !s) return s.error();
    return parser.take();
}

// (N, 6) or (N, 7) of float32 / float64, read a block of rows at a time.
Result<std::vector<Ray>> readNpyRays(std::FILE* in, int64_t size, const std::string& what,
                                     size_t maxRays) {
    auto header = readNpyHeader(in, size, what);
    if (!header) return header.error();
    const bool f4 = header->plain("<f4"), f8 = header->plain("<f8");
    const int64_t columns = header->shape.size() == 2 ? header->shape[1] : 0;
    if (!(f4 || f8) || (columns != 6 && columns != 7))
        return makeError(ErrorKind::InvalidInput,
                         "{}: rays must be float32 or float64 of shape (N, 6) [ox,oy,oz,dx,dy,dz] "
                         "or (N, 7) [..., tmax]; this is {} {}",
                         what,
                         header->fields.size() == 1 ? header->fields[0].type : "a structured dtype",
                         npyShapeText(header->shape));
    const size_t rows = size_t(header->shape[0]);
    if (rows > maxRays)
        return makeError(ErrorKind::InvalidInput, "{}: {} rays, more than {} (--max-rays)", what,
                         rows, maxRays);
    RayCollector collector(what, maxRays);
    const size_t rowBytes = size_t(columns) * (f4 ? 4 : 8);
    constexpr size_t kBlockRows = 4096;
    std::vector<unsigned char> block(kBlockRows * rowBytes);
    for (size_t row = 0; row < rows;) {
        const size_t n = std::min(kBlockRows, rows - row);
        if (std::fread(block.data(), rowBytes, n, in) != n)
            return makeError(ErrorKind::Io, "{}: read failed at row {}", what, row);
        for (size_t k = 0; k < n; ++k, ++row) {
            double v[7] = {};
            const unsigned char* p = block.data() + k * rowBytes;
            for (int64_t c = 0; c < columns; ++c) {
                if (f4) {
                    float x;
                    std::memcpy(&x, p + 4 * c, 4);
                    v[c] = x;
                } else {
                    std::memcpy(&v[c], p + 8 * c, 8);
                }
            }
            if (Status s = collector.add(v, int(columns), fmt::format("{}: row {}", what, row)); !s)
                return s.error();
        }
    }
    return collector.take();
}

template <class T>
void append(std::string& out, T value) {
    out.append(reinterpret_cast<const char*>(&value), sizeof value);
}

bool anyTmax(const std::vector<Ray>& rays) {
    return std::any_of(rays.begin(), rays.end(),
                       [](const Ray& r) { return std::isfinite(r.tMax); });
}

}  // namespace

bool isNpyPath(const std::string& path) { return hasExtension(path, ".npy"); }

Result<std::vector<Ray>> parseRays(std::string_view text, const std::string& what, size_t maxRays) {
    RayCollector parser(what, maxRays);
    while (!text.empty()) {
        const size_t nl = text.find('\n');
        if (Status s = parser.line(text.substr(0, nl)); !s) return s.error();
        text = nl == std::string_view::npos ? std::string_view() : text.substr(nl + 1);
    }
    return parser.take();
}

Result<std::vector<Ray>> decodeNpyRays(std::span<const unsigned char> bytes,
                                       const std::string& what, size_t maxRays) {
    // fmemopen needs a non-null buffer even for zero bytes.
    static unsigned char none = 0;
    void* data = bytes.empty() ? &none : const_cast<unsigned char*>(bytes.data());
    FilePtr in(::fmemopen(data, bytes.size(), "r"));
    if (!in) return makeError(ErrorKind::Io, "{}: cannot open: {}", what, std::strerror(errno));
    return readNpyRays(in.get(), int64_t(bytes.size()), what, maxRays);
}

Result<std::vector<Ray>> readRays(const std::string& path, size_t maxRays) {
    if (path == "-") return readCsvRays(stdin, "stdin", maxRays);
    int64_t size = 0;
    // A pipe given by name (/dev/stdin, <(...), a FIFO) is refused like every input; "-" reads one.
    auto file = openRegularFile(path, "a ray file (pipe rays in with --rays -)", &size);
    if (!file) return file.error();
    return isNpyPath(path) ? readNpyRays(file->get(), size, path, maxRays)
                           : readCsvRays(file->get(), path, maxRays);
}

std::string formatRays(const std::vector<Ray>& rays) {
    const bool tmax = anyTmax(rays);
    fmt::memory_buffer out;
    fmt::format_to(std::back_inserter(out), "ox,oy,oz,dx,dy,dz{}\n", tmax ? ",tmax" : "");
    // Nine significant digits give every float back exactly.
    for (const Ray& r : rays) {
        fmt::format_to(std::back_inserter(out), "{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g}",
                       r.origin.x, r.origin.y, r.origin.z, r.direction.x, r.direction.y,
                       r.direction.z);
        if (tmax) fmt::format_to(std::back_inserter(out), ",{:.9g}", r.tMax);
        out.push_back('\n');
    }
    return fmt::to_string(out);
}

std::string npyRays(const std::vector<Ray>& rays) {
    const bool tmax = anyTmax(rays);
    const NpyField f4[] = {{"", "<f4"}};
    const int64_t shape[] = {int64_t(rays.size()), tmax ? 7 : 6};
    std::string out = npyPreamble(f4, shape);
    out.reserve(out.size() + rays.size() * size_t(shape[1]) * 4);
    for (const Ray& r : rays) {
        for (int a = 0; a < 3; ++a) append(out, r.origin[a]);
        for (int a = 0; a < 3; ++a) append(out, r.direction[a]);
        if (tmax) append(out, r.tMax);
    }
    return out;
}

Status writeRays(const std::string& path, const std::vector<Ray>& rays) {
    return writeTextFile(path, isNpyPath(path) ? npyRays(rays) : formatRays(rays));
}

std::string formatHits(const std::vector<Hit>& hits) {
    fmt::memory_buffer out;
    fmt::format_to(std::back_inserter(out), "hit,t,x,y,z,steps,fetches\n");
    for (const Hit& h : hits) {
        if (h.hit)
            fmt::format_to(std::back_inserter(out), "1,{:.7g},{:.7g},{:.7g},{:.7g},{},{}\n", h.t,
                           h.position.x, h.position.y, h.position.z, h.steps, h.fetches);
        else
            fmt::format_to(std::back_inserter(out), "0,inf,nan,nan,nan,{},{}\n", h.steps,
                           h.fetches);
    }
    return fmt::to_string(out);
}

std::string npyHits(const std::vector<Hit>& hits) {
    const int64_t shape[] = {int64_t(hits.size())};
    std::string out = npyPreamble(kHitFields, shape);
    out.reserve(out.size() + hits.size() * 25);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (const Hit& h : hits) {
        append(out, uint8_t(h.hit ? 1 : 0));
        append(out, h.hit ? h.t : kInfinity);
        for (int a = 0; a < 3; ++a) append(out, h.hit ? h.position[a] : nan);
        append(out, int32_t(h.steps));
        append(out, int32_t(h.fetches));
    }
    return out;
}

Status writeHits(const std::string& path, const std::vector<Hit>& hits) {
    // "-": CSV on stdout, through the same mechanism.
    return writeTextFile(path, isNpyPath(path) ? npyHits(hits) : formatHits(hits));
}

}  // namespace relief
