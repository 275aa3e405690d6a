#include <relief/techniques/technique.h>

#include <relief/core/check.h>
#include <relief/core/parallel.h>

namespace relief {

std::string_view toString(Contract contract) {
    switch (contract) {
        case Contract::Exact: return "exact";
        case Contract::Conservative: return "conservative";
        case Contract::Approximate: return "approximate";
    }
    return "?";
}

void traceAll(const Tracer& tracer, std::span<const Ray> rays, std::span<Hit> hits) {
    RELIEF_CHECK(rays.size() == hits.size());
    if (tracer.prefersOneBatch()) {
        tracer.traceBatch(rays, hits);
        return;
    }
    parallelRanges(int64_t(rays.size()), 256, [&](int64_t begin, int64_t end) {
        tracer.traceBatch(rays.subspan(begin, end - begin), hits.subspan(begin, end - begin));
    });
}

double ParamValues::get(std::string_view name) const {
    auto it = m_values.find(name);
    RELIEF_CHECK(it != m_values.end());
    return it->second;
}

}  // namespace relief
