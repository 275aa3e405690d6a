// libFuzzer target: headerless samples (src/relief/io/raw_read.cpp) and the --raw option's parser.
// The input is the --raw text ("WxH:u8|u16|f32"), a newline, then the file's bytes.
// Seeds: fuzz/corpus/raw/.
#include "fuzz_common.h"

#include <algorithm>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace relief;
    const uint8_t* newline = std::find(data, data + size, uint8_t('\n'));
    if (newline == data + size) return 0;
    auto layout = parseRawLayout(std::string(data, newline));
    if (!layout) return 0;
    RELIEF_FUZZ_EXPECT(layout->width >= 1 && layout->height >= 1);
    LoadOptions options;
    options.maxSamples = fuzz::kFuzzMaxSamples;
    options.raw = *layout;
    const std::span<const unsigned char> bytes(newline + 1, data + size);
    if (auto hf = decodeHeightfield(bytes, "fuzz.raw", options)) {
        fuzz::checkHeightfield(*hf);
        RELIEF_FUZZ_EXPECT(hf->width == layout->width && hf->height == layout->height);
    }
    return 0;
}
