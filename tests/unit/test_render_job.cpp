// The render job (host/job/render_job.hpp): the one place where a pipeline becomes a file,
// bytes or an image, for every front end. The CLI's, serve's and Python's own tests check each
// front end's words; these check the job's rules themselves.
#include <fixpoint/host/core/config.hpp>
#include <fixpoint/host/core/pipeline.hpp>
#include <fixpoint/host/job/render_job.hpp>

#include "cli.hpp"
#include "configs.hpp"
#include "host.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <sys/stat.h>

namespace fs = std::filesystem;
using namespace fp;
using namespace fp::host;
using namespace fp::test;

namespace {

const std::string& small = small_circles;

Pipeline pipeline(const std::string& text, const std::string& name = "job.yaml") {
    return load_pipeline(fp::test::host().registry(), parse_config(text, name));
}

std::string dir(const std::string& name) { return fp::test::scratch_dir("render-job-" + name); }

} // namespace

// The default file: the config's output.path, else its stem + .png; never replaced unless named
// or forced, and the refusal points at output.path.
TEST(RenderJob, DefaultFileAndItsPromises) {
    const std::string d = dir("default");
    const std::string config = d + "/fig.yaml";
    fp::test::write_file(config, small);
    RenderRequest r;
    r.default_file = true;
    r.source = config;
    EXPECT_EQ(plan_render(pipeline(small, config), r).output, "fig.png");
    r.draft_name = true;
    EXPECT_EQ(plan_render(pipeline(small, config), r).output, "fig-draft.png");

    const std::string out = d + "/out.png";
    fp::test::write_file(out, "there before");
    const std::string with_path = small + "output: {path: " + out + "}\n";
    r.draft_name = false;
    EXPECT_EQ(error_of([&] { plan_render(pipeline(with_path, config), r); }),
              config + ":12:16: output.path: '" + out +
                  "' exists: name it with -o to replace it, or add --force");
    // Named, it may be replaced (the CLI's -o); serve asks for force whatever the name.
    r.output = out;
    EXPECT_EQ(plan_render(pipeline(small, config), r).output, out);
    r.named_replaces = false;
    r.replace_hint = "render with \"force\": true to replace it";
    EXPECT_EQ(error_of([&] { plan_render(pipeline(small, config), r); }),
              "'" + out + "' exists: render with \"force\": true to replace it");
    r.force = true;
    EXPECT_EQ(plan_render(pipeline(small, config), r).output, out);
    // The config itself, never.
    r.output = config;
    EXPECT_EQ(error_of([&] { plan_render(pipeline(small, config), r); }),
              "cannot write '" + config + "': it is the config being rendered");
}

// A front end's own rule runs first, and raster_only speaks in its words.
TEST(RenderJob, FrontEndRulesAndRasterOnly) {
    const std::string d = dir("rules");
    RenderRequest r;
    r.output = d + "/x.svg";
    r.raster_only = "cannot write {}: watch writes images (.png, .exr, .tif), not SVG or PDF";
    EXPECT_EQ(error_of([&] { plan_render(pipeline(small), r); }),
              "cannot write '" + d + "/x.svg': watch writes images (.png, .exr, .tif), not SVG or PDF");
    r.raster_only.clear();
    r.output = d + "/x.png";
    std::string seen;
    r.check_path = [&seen](const std::string& path, const Mark*) {
        seen = path;
        throw InputError("outside the root");
    };
    EXPECT_EQ(error_of([&] { plan_render(pipeline(small), r); }), "outside the root");
    EXPECT_EQ(seen, d + "/x.png");
}

// The preview's PNG in memory is the file the job writes, byte for byte.
TEST(RenderJob, EncodedBytesAreTheFile) {
    const std::string d = dir("encode");
    RenderRequest bytes;
    bytes.encode = Format::Png;
    bytes.threads = 2;
    RenderPlan a = plan_render(pipeline(small), bytes);
    const RenderResult ra = run_render(a);
    EXPECT_FALSE(ra.wrote);
    EXPECT_EQ(ra.width, 24);
    EXPECT_EQ(ra.height, 16);

    RenderRequest file;
    file.output = d + "/x.png";
    file.threads = 1;
    RenderPlan b = plan_render(pipeline(small), file);
    const RenderResult rb = run_render(b);
    EXPECT_TRUE(rb.wrote);
    EXPECT_EQ(rb.stats.samples, ra.stats.samples);
    ASSERT_GT(ra.bytes.size(), 8u);
    EXPECT_EQ(ra.bytes.substr(1, 3), "PNG");
    EXPECT_EQ(ra.bytes, fp::test::read_file(d + "/x.png"));
}

// A frame's folder is made by the job just before the frame is written; one that cannot be
// made is refused by the plan, before any render.
TEST(RenderJob, MakeFolderOnlyWhenWriting) {
    const std::string d = dir("folders");
    RenderRequest r;
    r.output = d + "/a/b/frame.png";
    r.make_folder = true;
    RenderPlan plan = plan_render(pipeline(small), r);
    EXPECT_FALSE(fs::exists(d + "/a")); // checked, not made
    run_render(plan);
    EXPECT_TRUE(fs::is_regular_file(d + "/a/b/frame.png"));

    fp::test::write_file(d + "/file", "");
    r.output = d + "/file/b/frame.png";
    EXPECT_EQ(error_of([&] { plan_render(pipeline(small), r); }),
              "cannot write '" + d + "/file/b/frame.png': '" + d + "/file' is not a folder");
    if (::geteuid() != 0) { // (root writes anywhere)
        fs::create_directory(d + "/locked");
        ::chmod((d + "/locked").c_str(), 0555);
        r.output = d + "/locked/b/frame.png";
        EXPECT_NE(error_of([&] { plan_render(pipeline(small), r); }).find("cannot make a folder in"),
                  std::string::npos);
        ::chmod((d + "/locked").c_str(), 0755);
    }
}

// A collection's child is checked but written by the collection (all or none); a render that drew
// nothing is refused at the renderer, unless the front end scores empty images (explore).
TEST(RenderJob, DeferredWriteAndEmptyImages) {
    const std::string d = dir("deferred");
    RenderRequest r;
    r.output = d + "/child.png";
    r.defer_write = true;
    r.keep_image = true;
    RenderPlan plan = plan_render(pipeline(small), r);
    const RenderResult res = run_render(plan);
    EXPECT_FALSE(fs::exists(d + "/child.png"));
    EXPECT_EQ(res.image.width, 24);
    EXPECT_EQ(res.image.pixels.size(), std::size_t(24 * 16 * 3));

    // The view far from the circles' attractor: nothing lands.
    const std::string empty =
        fp::test::replace_once(small, "view: [-2, 2, -1.5, 1.5]", "view: [50, 51, 50, 51]");
    RenderRequest e;
    e.keep_image = true;
    RenderPlan refused = plan_render(pipeline(empty), e);
    const std::string why = error_of([&] { run_render(refused); });
    EXPECT_EQ(why.rfind("job.yaml:2:3: renderer: nothing was drawn (0 of 4000 points", 0), 0u) << why;
    e.allow_empty = true;
    RenderPlan scored = plan_render(pipeline(empty), e);
    EXPECT_EQ(run_render(scored).stats.drawn, 0u);
}

// The summary line every front end shows, from one place.
TEST(RenderJob, SummaryLine) {
    RenderRequest r;
    r.keep_image = true;
    r.threads = 2;
    RenderPlan plan = plan_render(pipeline(small), r);
    const RenderResult res = run_render(plan);
    const std::string line = summary_line(plan, res);
    EXPECT_EQ(line.rfind("render: 4000 points in ", 0), 0u) << line;
    EXPECT_NE(line.find("points/s, 2 threads, "), std::string::npos) << line;
    EXPECT_NE(line.find(" restarted chain"), std::string::npos) << line;
}
