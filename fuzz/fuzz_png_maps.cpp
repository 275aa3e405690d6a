// libFuzzer target: PNG map files (src/relief/io/map_png.cpp, its own libpng reader with the
// relief text chunks), through readMapFile as --maps FILE reads them. Seeds: fuzz/corpus/png_maps/.
#include "fuzz_maps.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    relief::fuzz::checkMapBytes({data, size}, "fuzz.maps.png");
    return 0;
}
