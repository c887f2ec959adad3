// The test picture of colour stealing (the superfractal's and the chaos game's tests): a small
// PNG whose every cell is known, and an image's pixels as 8-bit values.
#pragma once

#include <fixpoint/host/core/image_io.hpp>

#include <cstddef>
#include <string>
#include <vector>

namespace fp::test {

/// A picture of w x h 8-bit colours, written as dir/picture.png: pixel (col, row from the top)
/// has red 10 + 20 col, green 10 + 20 row, blue 255 on the diagonal and 200 off it.
inline std::string write_picture(const std::string& dir, int w, int h) {
    fp::Image img;
    img.width = w;
    img.height = h;
    img.channels = 3;
    for (int row = 0; row < h; ++row)
        for (int col = 0; col < w; ++col) {
            img.pixels.push_back(float(10 + 20 * col) / 255.0f);
            img.pixels.push_back(float(10 + 20 * row) / 255.0f);
            img.pixels.push_back(float(col == row ? 255 : 200) / 255.0f);
        }
    std::string path = dir + "/picture.png";
    fp::host::write_image(img, path, 8, "");
    return path;
}

/// Pixel k of an RGB image as 8-bit values.
inline std::vector<int> pixel8(const fp::Image& img, std::size_t k) {
    std::vector<int> out;
    for (std::size_t c = 0; c < 3; ++c) out.push_back(int(img.pixels[3 * k + c] * 255.0f + 0.5f));
    return out;
}

} // namespace fp::test
