#include <fmt/format.h>
#include <relief/io/image_write.h>
#include <relief/io/ray_io.h>
#include <relief/io/read_common.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace relief {

namespace {

// Parses exactly six comma-separated numbers; false if the line has another shape.
bool parseSix(std::string_view line, float (&v)[6]) {
    std::string copy(line);
    const char* p = copy.c_str();
    for (int k = 0; k < 6; ++k) {
        char* end = nullptr;
        v[k] = std::strtof(p, &end);
        if (end == p) return false;
        p = end;
        while (*p == ' ' || *p == '\t' || *p == '\r') ++p;
        if (k < 5) {
            if (*p != ',') return false;
            ++p;
        }
    }
    return *p == '\0';
}

bool isBlank(std::string_view line) {
    return line.find_first_not_of(" \t\r") == std::string_view::npos;
}

// Rays one line at a time, so that a limit stops the read where it is reached.
class RayParser {
  public:
    RayParser(const std::string& what, size_t maxRays) : m_what(what), m_maxRays(maxRays) {}

    Status line(std::string_view line) {
        ++m_lineNumber;
        if (line.find('\0') != std::string_view::npos)
            return makeError(ErrorKind::InvalidInput,
                             "{}:{}: NUL byte in a ray line (not a text file?)", m_what,
                             m_lineNumber);
        if (line.size() > kMaxRayLineBytes)
            return makeError(ErrorKind::InvalidInput, "{}:{}: line longer than {} bytes", m_what,
                             m_lineNumber, kMaxRayLineBytes);
        if (isBlank(line)) return {};
        float v[6];
        if (!parseSix(line, v)) {
            const bool header =
                m_lineNumber == 1 && line.find_first_of("0123456789") == std::string_view::npos;
            if (header) return {};
            return makeError(ErrorKind::InvalidInput,
                             "{}:{}: expected six numbers ox,oy,oz,dx,dy,dz", m_what, m_lineNumber);
        }
        auto ray = checkedRay(v);
        if (!ray)
            return makeError(ray.error().kind, "{}:{}: {}", m_what, m_lineNumber,
                             ray.error().message);
        if (m_rays.size() >= m_maxRays)
            return makeError(ErrorKind::InvalidInput, "{}:{}: more than {} rays (--max-rays)",
                             m_what, m_lineNumber, m_maxRays);
        m_rays.push_back(*ray);
        return {};
    }
    std::vector<Ray> take() { return std::move(m_rays); }

  private:
    const std::string& m_what;
    size_t m_maxRays;
    size_t m_lineNumber = 0;
    std::vector<Ray> m_rays;
};

}  // namespace

Result<Ray> checkedRay(const float (&v)[6]) {
    for (float x : v)
        if (!std::isfinite(x)) return makeError(ErrorKind::InvalidInput, "non-finite value in ray");
    for (int k = 0; k < 3; ++k)
        if (std::abs(double(v[k])) > kMaxRayOrigin)
            return makeError(ErrorKind::InvalidInput,
                             "origin coordinate {:g} is too far for float precision "
                             "(at most {:g} texels from the origin)",
                             v[k], kMaxRayOrigin);
    const vec3 d(v[3], v[4], v[5]);
    const float length = glm::length(d);
    if (!(length > 0.0f) || !std::isfinite(length))
        return makeError(ErrorKind::InvalidInput, "zero or unusable direction");
    return Ray{vec3(v[0], v[1], v[2]), d / length, kInfinity};
}

Result<std::vector<Ray>> parseRays(std::string_view text, const std::string& what, size_t maxRays) {
    RayParser parser(what, maxRays);
    while (!text.empty()) {
        const size_t nl = text.find('\n');
        if (Status s = parser.line(text.substr(0, nl)); !s) return s.error();
        text = nl == std::string_view::npos ? std::string_view() : text.substr(nl + 1);
    }
    return parser.take();
}

Result<std::vector<Ray>> readRays(const std::string& path, size_t maxRays) {
    FilePtr owned;
    std::FILE* in = stdin;
    if (path != "-") {
        auto file = openRegularFile(path, "a ray file");
        if (!file) return file.error();
        owned = std::move(*file);
        in = owned.get();
    }
    const std::string what = path == "-" ? std::string("stdin") : path;
    RayParser parser(what, maxRays);
    // Lines are read in pieces of at most one overlong line, so no input grows memory unbounded.
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

std::string formatHits(const std::vector<Hit>& hits) {
    fmt::memory_buffer out;
    fmt::format_to(std::back_inserter(out), "hit,t,x,y,z,steps\n");
    for (const Hit& h : hits) {
        if (h.hit)
            fmt::format_to(std::back_inserter(out), "1,{:.7g},{:.7g},{:.7g},{:.7g},{}\n", h.t,
                           h.position.x, h.position.y, h.position.z, h.steps);
        else
            fmt::format_to(std::back_inserter(out), "0,inf,nan,nan,nan,{}\n", h.steps);
    }
    return fmt::to_string(out);
}

Status writeHits(const std::string& path, const std::vector<Hit>& hits) {
    return writeTextFile(path, formatHits(hits));  // "-": stdout, through the same mechanism
}

}  // namespace relief
