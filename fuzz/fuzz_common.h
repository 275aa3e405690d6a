#pragma once
// What the libFuzzer targets share: the image readers run on the input bytes through the
// in-memory entry points (heightfield_io.h), and what they return is checked, so that a reader
// which "succeeds" with a wrong result is a finding too, not only a crash or a sanitizer report.
#include <relief/io/heightfield_io.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <span>

namespace relief::fuzz {

// Small enough that a header claiming a large image is refused before a big allocation, so the
// fuzzer spends its time in the decoders (the limit itself is tested in tests/io_test.cpp).
inline constexpr int64_t kFuzzMaxSamples = int64_t(1) << 22;

#define RELIEF_FUZZ_EXPECT(cond)                                                        \
    do {                                                                                \
        if (!(cond)) {                                                                  \
            std::fprintf(stderr, "%s:%d: expectation failed: %s\n", __FILE__, __LINE__, \
                         #cond);                                                        \
            std::abort();                                                               \
        }                                                                               \
    } while (false)

// A loaded heightfield has its stated size and every sample finite in [0, 1] (DESIGN §1).
inline void checkHeightfield(const Heightfield& hf) {
    RELIEF_FUZZ_EXPECT(hf.width >= 1 && hf.height >= 1);
    RELIEF_FUZZ_EXPECT(int64_t(hf.width) * hf.height <= kFuzzMaxSamples);
    RELIEF_FUZZ_EXPECT(hf.samples.size() == size_t(hf.width) * size_t(hf.height));
    for (float v : hf.samples) RELIEF_FUZZ_EXPECT(std::isfinite(v) && v >= 0.0f && v <= 1.0f);
}

// Every file format reader sees the bytes (the format comes from the content, as for files): as
// a heightfield, with a channel chosen by the input's size so that all of them get exercised,
// and as a colour image.
inline void decodeImageBytes(std::span<const unsigned char> bytes, const char* name) {
    LoadOptions options;
    options.maxSamples = kFuzzMaxSamples;
    options.channel = ChannelSelect(bytes.size() % 5);
    if (auto hf = decodeHeightfield(bytes, name, options)) {
        checkHeightfield(*hf);
    } else {
        RELIEF_FUZZ_EXPECT(!hf.error().message.empty());
    }
    if (auto image = decodeColorImage(bytes, name, kFuzzMaxSamples)) {
        RELIEF_FUZZ_EXPECT(image->width >= 1 && image->height >= 1);
        RELIEF_FUZZ_EXPECT(image->pixels.size() == size_t(image->width) * size_t(image->height));
    }
}

}  // namespace relief::fuzz
