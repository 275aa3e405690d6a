#include <relief/techniques/technique.h>

#include <relief/core/check.h>

namespace relief {

std::string_view toString(Contract contract) {
    switch (contract) {
        case Contract::Exact: return "exact";
        case Contract::Conservative: return "conservative";
        case Contract::Approximate: return "approximate";
    }
    return "?";
}

double ParamValues::get(std::string_view name) const {
    auto it = m_values.find(name);
    RELIEF_CHECK(it != m_values.end());
    return it->second;
}

}  // namespace relief
