#pragma once
// Writing images. Every writer goes through a temporary file in the target folder and renames it
// on success, so a failed or interrupted write leaves no partial file and the old one untouched.
#include <relief/core/error.h>
#include <relief/core/image.h>

#include <functional>
#include <string>

namespace relief {

Status writePng(const std::string& path, const ImageRgb8& image);
Status writeExr(const std::string& path, const ImageF& image);  // one float channel "Y"

// Writes `text` to path through a temporary file.
Status writeTextFile(const std::string& path, const std::string& text);

// Runs `write(tempPath)` then renames tempPath to path; removes the temp file on failure.
Status writeAtomically(const std::string& path,
                       const std::function<Status(const std::string& tempPath)>& write);

}  // namespace relief
