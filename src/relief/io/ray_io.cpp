#include <relief/io/ray_io.h>

#include <relief/io/image_write.h>

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

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

}  // namespace

Result<std::vector<Ray>> parseRays(std::string_view text, const std::string& what) {
    std::vector<Ray> rays;
    size_t lineNumber = 0;
    while (!text.empty()) {
        const size_t nl = text.find('\n');
        const std::string_view line = text.substr(0, nl);
        text = nl == std::string_view::npos ? std::string_view() : text.substr(nl + 1);
        ++lineNumber;
        if (isBlank(line)) continue;
        float v[6];
        if (!parseSix(line, v)) {
            const bool header = lineNumber == 1 && line.find_first_of("0123456789") == std::string_view::npos;
            if (header) continue;
            return makeError(ErrorKind::InvalidInput,
                             "{}:{}: expected six numbers ox,oy,oz,dx,dy,dz", what, lineNumber);
        }
        for (float x : v)
            if (!std::isfinite(x))
                return makeError(ErrorKind::InvalidInput, "{}:{}: non-finite value in ray", what,
                                 lineNumber);
        const vec3 d(v[3], v[4], v[5]);
        const float length = glm::length(d);
        if (!(length > 0.0f) || !std::isfinite(length))
            return makeError(ErrorKind::InvalidInput, "{}:{}: zero or unusable direction", what,
                             lineNumber);
        if (rays.size() >= kMaxRaysPerFile)
            return makeError(ErrorKind::InvalidInput, "{}: more than {} rays", what, kMaxRaysPerFile);
        rays.push_back(Ray{vec3(v[0], v[1], v[2]), d / length, kInfinity});
    }
    return rays;
}

Result<std::vector<Ray>> readRays(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return makeError(ErrorKind::Io, "{}: cannot open ray file", path);
    std::ostringstream buffer;
    buffer << in.rdbuf();
    if (in.bad()) return makeError(ErrorKind::Io, "{}: read failed", path);
    return parseRays(buffer.str(), path);
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
