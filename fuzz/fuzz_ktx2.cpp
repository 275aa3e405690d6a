// libFuzzer target: KTX2 map files (src/relief/io/map_ktx2.cpp, the hand-written reader), through
// readMapFile as --maps FILE reads them. Seeds: fuzz/corpus/ktx2/ (relief bake ... -o X.ktx2).
#include "fuzz_maps.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    relief::fuzz::checkMapBytes({data, size}, "fuzz.maps.ktx2");
    return 0;
}
