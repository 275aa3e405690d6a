#pragma once
// Writing images and text through the one output mechanism (output.h): a regular file is replaced
// atomically, a device / FIFO / "-" is streamed to, anything else is refused. The OutputSet
// overloads add to one transaction; the others write one output on their own.
#include <relief/core/error.h>
#include <relief/core/image.h>
#include <relief/io/output.h>

#include <functional>
#include <string>

namespace relief {

Status writePng(OutputSet& outputs, const std::string& path, const ImageRgb8& image);
Status writeExr(OutputSet& outputs, const std::string& path, const ImageF& image);  // channel "Y"
// A float image as PFM ("Pf", little endian, rows bottom to top as the format stores them: what
// io/pfm_read.cpp reads) or as .npy float32 of shape (H, W), row 0 at the top.
Status writePfm(OutputSet& outputs, const std::string& path, const ImageF& image);
Status writeNpy(OutputSet& outputs, const std::string& path, const ImageF& image);
// The format from the extension: .npy, .pfm, else OpenEXR.
Status writeFloatImage(OutputSet& outputs, const std::string& path, const ImageF& image);
Status writePng(const std::string& path, const ImageRgb8& image);
Status writeExr(const std::string& path, const ImageF& image);

Status writeTextFile(const std::string& path, const std::string& text);

// Runs `write(tempPath)` into a temp file, then puts it in place (one output's transaction).
Status writeAtomically(const std::string& path,
                       const std::function<Status(const std::string& tempPath)>& write);

}  // namespace relief
