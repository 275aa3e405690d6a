#pragma once
// NumPy .npy files (format versions 1.0 and 2.0), written and read by hand: Debian packages no
// C++ npy library, and relief needs only little-endian, C-order arrays of a plain dtype or a
// packed structured one. The reader refuses what it cannot honour with a message: a bad magic
// or version, a header that is not the dict NumPy writes, big-endian or unknown types,
// fortran_order=True, shapes whose size overflows, and data shorter or longer than the shape.
#include <relief/core/error.h>

#include <cstdint>
#include <cstdio>
#include <span>
#include <string>
#include <vector>

namespace relief {

// One field of a dtype: `name` is empty for a plain dtype; `type` is NumPy's type string
// ('<f4', '|b1', ...), little endian or byte-order free.
struct NpyField {
    std::string name;
    std::string type;
};

struct NpyHeader {
    std::vector<NpyField> fields;  // one unnamed field for a plain dtype
    std::vector<int64_t> shape;
    int64_t dataOffset = 0;  // bytes before the data
    int64_t itemBytes = 0;   // bytes of one element (the sum of the fields')
    int64_t elements = 0;    // the product of the shape

    bool plain(std::string_view type) const {
        return fields.size() == 1 && fields[0].name.empty() && fields[0].type == type;
    }
};

// NumPy refuses headers longer than this by default (np.load's max_header_size); so does relief.
inline constexpr int64_t kMaxNpyHeaderBytes = 10000;

// The bytes before the data: magic, version 1.0, header dict padded to a multiple of 64.
std::string npyPreamble(std::span<const NpyField> fields, std::span<const int64_t> shape);

// Reads and checks the preamble at the stream's position (0), and that the data after it is
// exactly what the shape needs in a file of `fileSize` bytes. The stream is left at the data.
Result<NpyHeader> readNpyHeader(std::FILE* in, int64_t fileSize, const std::string& what);

// The shape as NumPy prints it, "(N, 6)", for messages.
std::string npyShapeText(std::span<const int64_t> shape);

}  // namespace relief
