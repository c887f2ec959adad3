// output.tiled's rule (host/image_io.hpp's tiled_file): by default TIFF and EXR images of more
// than 2^26 pixels (8192 x 8192) are tiled, PNG never; `true` and `false` say so whatever the
// size, and `true` for a PNG is refused.
#include <fixpoint/host/core/image_io.hpp>

#include <gtest/gtest.h>

using fp::host::Tiled;
using fp::host::tiled_file;

TEST(Tiled, AutoTilesTheLargestTiffAndExr) {
    EXPECT_FALSE(tiled_file("a.tif", 8192, 8192, Tiled::Auto));
    EXPECT_TRUE(tiled_file("a.tif", 8193, 8192, Tiled::Auto));
    EXPECT_TRUE(tiled_file("a.TIFF", 30000, 30000, Tiled::Auto));
    EXPECT_FALSE(tiled_file("a.exr", 4096, 16384, Tiled::Auto));
    EXPECT_TRUE(tiled_file("a.exr", 4097, 16384, Tiled::Auto));
    EXPECT_FALSE(tiled_file("a.png", 30000, 30000, Tiled::Auto));
}

TEST(Tiled, GivenItIsObeyed) {
    EXPECT_TRUE(tiled_file("a.tif", 16, 16, Tiled::Yes));
    EXPECT_TRUE(tiled_file("a.exr", 16, 16, Tiled::Yes));
    EXPECT_FALSE(tiled_file("a.tif", 30000, 30000, Tiled::No));
    EXPECT_FALSE(tiled_file("a.png", 30000, 30000, Tiled::No));
    try {
        tiled_file("a.png", 16, 16, Tiled::Yes);
        ADD_FAILURE() << "a tiled PNG";
    } catch (const fp::InputError& e) {
        EXPECT_STREQ(e.what(),
                     "output.tiled: 'a.png': only TIFF and EXR images have tiles (write .tif or .exr)");
    }
}
