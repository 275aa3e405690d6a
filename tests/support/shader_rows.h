#pragma once
// The registry rows that declare an engine shader-library function (shaders/relief/), and a test
// name per row: the shader-library suites of relief_tests and relief_gl_tests run over them.
#include <gtest/gtest.h>
#include <relief/techniques/registry.h>

#include <cctype>
#include <string>
#include <string_view>
#include <vector>

namespace relief::testing {

inline std::vector<const TechniqueInfo*> shaderLibraryRows() {
    std::vector<const TechniqueInfo*> rows;
    for (const TechniqueInfo& info : techniques())
        if (!info.shaderFunction.empty()) rows.push_back(&info);
    return rows;
}

// `text` with every character that is not a letter or digit replaced by '_'.
inline std::string identifierFrom(std::string_view text) {
    std::string name;
    for (char c : text) name += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
    return name;
}

inline std::string rowTestName(const ::testing::TestParamInfo<const TechniqueInfo*>& p) {
    return identifierFrom(p.param->name);
}

}  // namespace relief::testing
