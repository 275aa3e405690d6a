// libFuzzer target: PNG (libpng), src/relief/io/png_read.cpp, through the heightfield and colour
// readers. Seeds: fuzz/corpus/png/.
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    relief::fuzz::decodeImageBytes({data, size}, "fuzz.png");
    return 0;
}
