// stb_image's implementation, compiled with the fuzz build's sanitizers and coverage (the normal
// build links Debian's libstb.so instead). Only the JPEG decoder is used by relief.
#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>
