// libFuzzer target: PFM, src/relief/io/pfm_read.cpp, through the heightfield and colour
// readers. Seeds: fuzz/corpus/pfm/.
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    relief::fuzz::decodeImageBytes({data, size}, "fuzz.pfm");
    return 0;
}
