// libFuzzer target: OpenEXR heightfields, src/relief/io/exr_read.cpp, through the heightfield and colour
// readers. Seeds: fuzz/corpus/exr/.
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    relief::fuzz::decodeImageBytes({data, size}, "fuzz.exr");
    return 0;
}
