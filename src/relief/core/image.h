#pragma once
// A 2D array of pixels, row 0 at the top.
#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace relief {

template <class T>
struct Image {
    int width = 0;
    int height = 0;
    std::vector<T> pixels;

    Image() = default;
    Image(int w, int h, T fill = T{}) : width(w), height(h), pixels(size_t(w) * size_t(h), fill) {}
    T& at(int x, int y) { return pixels[size_t(y) * size_t(width) + size_t(x)]; }
    const T& at(int x, int y) const { return pixels[size_t(y) * size_t(width) + size_t(x)]; }
};

using Rgb8 = glm::u8vec3;
using ImageRgb8 = Image<Rgb8>;
using ImageRgbF = Image<glm::vec3>;
using ImageF = Image<float>;

}  // namespace relief
