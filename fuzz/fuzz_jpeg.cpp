// libFuzzer target: JPEG (the marker walk, then libjpeg-turbo), src/relief/io/jpeg_read.cpp, through the heightfield and colour
// readers. Seeds: fuzz/corpus/jpeg/.
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    relief::fuzz::decodeImageBytes({data, size}, "fuzz.jpeg");
    return 0;
}
