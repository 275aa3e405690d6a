#include <relief/io/read_common.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>

namespace relief {

namespace {

const char* fileTypeName(mode_t mode) {
    if (S_ISDIR(mode)) return "a directory";
    if (S_ISFIFO(mode)) return "a FIFO (pipe)";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISSOCK(mode)) return "a socket";
    return "not a regular file";
}

}  // namespace

Result<FilePtr> openRegularFile(const std::string& path, std::string_view what, int64_t* size) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    if (fd < 0) return makeError(ErrorKind::Io, "{}: cannot open: {}", path, std::strerror(errno));
    struct stat info {};
    if (::fstat(fd, &info) != 0) {
        const int error = errno;
        ::close(fd);
        return makeError(ErrorKind::Io, "{}: cannot open: {}", path, std::strerror(error));
    }
    // Pipes and devices have no size and may block or never end; every reader here needs a file.
    if (!S_ISREG(info.st_mode)) {
        ::close(fd);
        return makeError(ErrorKind::Io, "{}: cannot open: is {}, not {}", path,
                         fileTypeName(info.st_mode), what);
    }
    // Regular files never block; clearing the flag keeps stdio's reads ordinary.
    ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
    FilePtr file(::fdopen(fd, "rb"));
    if (!file) {
        const int error = errno;
        ::close(fd);
        return makeError(ErrorKind::Io, "{}: cannot open: {}", path, std::strerror(error));
    }
    if (size) *size = int64_t(info.st_size);
    return file;
}

Result<FileReader> FileReader::open(const std::string& path) {
    FileReader reader;
    reader.m_path = path;
    auto file = openRegularFile(path, "an image file", &reader.m_size);
    if (!file) return file.error();
    reader.m_file = std::move(*file);
    reader.readHead();
    if (!reader.seek(0)) return makeError(ErrorKind::Io, "{}: cannot read", path);
    return reader;
}

Result<FileReader> FileReader::fromMemory(std::span<const unsigned char> bytes, std::string name) {
    FileReader reader;
    reader.m_path = std::move(name);
    // fmemopen only reads in mode "r"; it needs a non-null buffer even for zero bytes.
    static unsigned char none = 0;
    void* data = bytes.empty() ? &none : const_cast<unsigned char*>(bytes.data());
    reader.m_file.reset(::fmemopen(data, bytes.size(), "r"));
    if (!reader.m_file)
        return makeError(ErrorKind::Io, "{}: cannot open: {}", reader.m_path, std::strerror(errno));
    reader.m_size = int64_t(bytes.size());
    reader.readHead();
    if (!reader.seek(0)) return makeError(ErrorKind::Io, "{}: cannot read", reader.m_path);
    return reader;
}

void FileReader::readHead() {
    m_headSize = std::fread(m_head.data(), 1, m_head.size(), m_file.get());
}

bool FileReader::read(void* data, size_t bytes) {
    return std::fread(data, 1, bytes, m_file.get()) == bytes;
}

bool FileReader::seek(int64_t offset) {
    return ::fseeko(m_file.get(), off_t(offset), SEEK_SET) == 0;
}

int64_t FileReader::tell() { return int64_t(::ftello(m_file.get())); }

Result<std::vector<unsigned char>> FileReader::readAll() {
    std::vector<unsigned char> bytes(static_cast<size_t>(m_size));
    if (!seek(0) || !read(bytes.data(), bytes.size()))
        return makeError(ErrorKind::Io, "{}: read failed", m_path);
    return bytes;
}

FileFormat detectFormat(std::span<const unsigned char> head) {
    auto startsWith = [head](std::initializer_list<unsigned char> magic) {
        return head.size() >= magic.size() && std::equal(magic.begin(), magic.end(), head.begin());
    };
    if (startsWith({0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'})) return FileFormat::Png;
    if (startsWith({0xff, 0xd8, 0xff})) return FileFormat::Jpeg;
    if (startsWith({0x76, 0x2f, 0x31, 0x01})) return FileFormat::Exr;
    const bool spaceAfterTwo = head.size() > 2 && std::isspace(head[2]);
    if ((startsWith({'P', 'F'}) || startsWith({'P', 'f'})) && spaceAfterTwo) return FileFormat::Pfm;
    return FileFormat::Unknown;
}

namespace {

size_t scalarBytes(Scalar scalar) {
    switch (scalar) {
        case Scalar::U8: return 1;
        case Scalar::U16: return 2;
        case Scalar::F32: return 4;
    }
    return 1;
}

uint32_t loadUnsigned(const unsigned char* p, size_t bytes, std::endian endian) {
    uint32_t value = 0;
    for (size_t k = 0; k < bytes; ++k)
        value = value << 8 | p[endian == std::endian::big ? k : bytes - 1 - k];
    return value;
}

float loadScalar(const unsigned char* p, Scalar scalar, std::endian endian) {
    const uint32_t bits = loadUnsigned(p, scalarBytes(scalar), endian);
    switch (scalar) {
        case Scalar::U8: return float(bits) / 255.0f;
        case Scalar::U16: return float(bits) / 65535.0f;
        case Scalar::F32: return std::bit_cast<float>(bits);
    }
    return 0.0f;
}

float pickChannel(const float* pixel, int channels, ChannelSelect select) {
    const bool colour = channels >= 3;
    switch (select) {
        case ChannelSelect::Luminance:
            return colour ? 0.2126f * pixel[0] + 0.7152f * pixel[1] + 0.0722f * pixel[2]
                          : pixel[0];
        case ChannelSelect::Red: return pixel[0];
        case ChannelSelect::Green: return pixel[colour ? 1 : 0];
        case ChannelSelect::Blue: return pixel[colour ? 2 : 0];
        case ChannelSelect::Alpha: return pixel[channels - 1];  // checkChannel saw 2 or 4
    }
    return pixel[0];
}

}  // namespace

size_t rowBytes(const PixelLayout& layout, int64_t width) {
    return size_t(width) * size_t(layout.channels) * scalarBytes(layout.scalar);
}

int64_t imageBytes(const PixelLayout& layout, int64_t width, int64_t height) {
    auto inLimit = [](int64_t n) { return n > 0 && n <= kMaxDimension; };
    if (!inLimit(width) || !inLimit(height)) return -1;
    return int64_t(rowBytes(layout, width)) * height;
}

Status checkChannel(const std::string& path, int channels, ChannelSelect select) {
    if (select == ChannelSelect::Alpha && channels != 2 && channels != 4)
        return makeError(ErrorKind::BadArgument, "--channel a: {} has no alpha channel", path);
    return {};
}

void convertRow(const unsigned char* row, const PixelLayout& layout, int64_t width,
                ChannelSelect select, float* out) {
    const size_t bytes = scalarBytes(layout.scalar);
    const size_t stride = bytes * size_t(layout.channels);
    float pixel[4];
    for (int64_t i = 0; i < width; ++i, row += stride) {
        for (int c = 0; c < layout.channels; ++c)
            pixel[c] = loadScalar(row + size_t(c) * bytes, layout.scalar, layout.endian);
        out[i] = pickChannel(pixel, layout.channels, select);
    }
}

Status readRows(FileReader& file, const PixelLayout& layout, ChannelSelect select, bool bottomUp,
                int64_t width, std::span<float> out) {
    const int64_t rows = int64_t(out.size()) / width;
    std::vector<unsigned char> row(rowBytes(layout, width));
    for (int64_t r = 0; r < rows; ++r) {
        if (!file.read(row.data(), row.size()))
            return makeError(ErrorKind::InvalidInput,
                             "{}: truncated: the file ends at row {} of {}", file.path(), r, rows);
        const int64_t y = bottomUp ? rows - 1 - r : r;
        convertRow(row.data(), layout, width, select, out.data() + y * width);
    }
    return {};
}

}  // namespace relief
