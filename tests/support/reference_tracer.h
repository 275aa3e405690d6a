#pragma once
// The reference (the registry's `exact` row, DESIGN §3) one ray at a time, for tests that compare
// another tracer with it ray by ray. Tests outside techniques/exact/ reach it through the registry.
#include <relief/core/check.h>
#include <relief/techniques/registry.h>

#include <memory>

namespace relief::testing {

class ReferenceTracer {
public:
    explicit ReferenceTracer(std::shared_ptr<const Surface> surface) {
        auto tracer = createTracer(referenceTechnique().name, std::move(surface));
        RELIEF_CHECK(tracer);
        m_tracer = std::move(*tracer);
    }
    Hit trace(const Ray& ray) const {
        Hit hit;
        m_tracer->traceBatch({&ray, 1}, {&hit, 1});
        return hit;
    }

private:
    std::unique_ptr<Tracer> m_tracer;
};

}  // namespace relief::testing
