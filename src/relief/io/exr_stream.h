#pragma once
// What the OpenEXR readers and writers share (internal to src/relief/io; heightfields in
// exr_read.cpp, maps in map_file.cpp, images in image_write.cpp): input through a FileReader, so
// that files and bytes in memory decode alike, the checks made before OpenEXR sees a header and
// the size of its worker pool (both in exr_common.cpp). Stream errors are thrown as OpenEXR's own
// exceptions, which its callers already catch.
#include <relief/io/read_common.h>

#include <Iex.h>
#include <ImfIO.h>

#include <optional>
#include <string>

namespace relief {

// Sets OpenEXR's process-wide image and tile size limits to kMaxDimension (once).
void limitExrSizes();

// The threads an OpenEXR reader or writer (de)compresses with: the process's thread limit
// (ThreadLimit), after sizing OpenEXR's own worker pool to it. Its default pool is empty, so a
// file's zip blocks were compressed one after another (1.1–1.3 s of a 12 s safety-cc bake at 1024²
// on 2 threads) and read back one after another (half of `relief render --maps` on those maps).
// The bytes and the floats read are the same either way: each block is compressed on its own and
// written in order; OpenEXR reads the stream on the calling thread and rethrows a worker's error.
int exrThreads();

// OpenEXR allocates an attribute's declared size before reading its value, so a damaged size
// field in a file of a few bytes costs gigabytes. Walks the header(s) and says what is wrong if an
// attribute claims more bytes than the file has left (nothing if all is well); leaves the file
// at position 0.
std::optional<std::string> exrHeaderProblem(FileReader& file);

class ExrInputStream final : public Imf::IStream {
public:
    // Reads from the file's current position (0 for a fresh FileReader).
    explicit ExrInputStream(FileReader& file) : Imf::IStream(file.path().c_str()), m_file(file) {}

    // Reads n bytes or throws; returns false once the last byte has been read.
    bool read(char c[], int n) override {
        if (n < 0 || !m_file.read(c, size_t(n)))
            throw Iex::InputExc("early end of file: fewer than " + std::to_string(n) +
                                " bytes left to read");
        return m_file.tell() < m_file.size();
    }

    uint64_t tellg() override { return uint64_t(m_file.tell()); }
    FileReader& file() { return m_file; }

    void seekg(uint64_t pos) override {
        if (pos > uint64_t(m_file.size()) || !m_file.seek(int64_t(pos)))
            throw Iex::InputExc("seek to byte " + std::to_string(pos) + " beyond the end of file");
    }

private:
    FileReader& m_file;
};

}  // namespace relief
