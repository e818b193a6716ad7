// Record: the frames are the window's pixels (the last one equals the screenshot of the same
// frame), compressed (at least 5x smaller than the same image stored uncompressed in a PNG),
// and with ffmpeg the MP4 has one video frame per PNG at the window's size.
#include <gtest/gtest.h>

#include "viewer_run.hpp"

using namespace frnn::test;

namespace {
/// The size of a PNG holding `img` in stored (uncompressed) deflate blocks: the signature and
/// the IHDR, IDAT and IEND chunks (57 bytes), zlib's header and checksum (6), a filter byte per
/// row and 5 bytes per stored block of at most 65,535 bytes.
std::size_t stored_png_size(const frnn::sim::image& img) {
    const std::size_t raw = std::size_t(img.height) * (1 + 3 * std::size_t(img.width));
    return 57 + 6 + raw + 5 * ((raw + 65534) / 65535);
}
}  // namespace

TEST(ViewerRecord, FramesAreTheWindowsPixelsCompressedAndMakeAnMp4) {
    const scratch_dir dir("viewer_record");
    write_text(dir / "script.json", R"({"steps_per_frame": 1, "actions": [{"frame": 2, "do": "record", "dir": "rec"}]})");
    const auto r = run_viewer(dir, "--scene droplet --dim 2 --particles 400 --script script.json --frames 6 --screenshot last.png");
    ASSERT_EQ(r.code, 0) << r.err;
    // Frames 2 to 5: four PNGs, the last drawn when the screenshot was taken.
    EXPECT_TRUE(std::filesystem::exists(dir / "rec" / "frame_00003.png"));
    EXPECT_FALSE(std::filesystem::exists(dir / "rec" / "frame_00004.png"));
    const std::string png = slurp(dir / "rec" / "frame_00003.png");
    const auto frame = frnn::sim::decode_png(png);
    const auto shot = frnn::sim::decode_png(slurp(dir / "last.png"));
    EXPECT_EQ(frame.width, 960);
    EXPECT_EQ(frame.height, 600);
    EXPECT_EQ(frame.rgb, shot.rgb);
    EXPECT_LE(5 * png.size(), stored_png_size(frame)) << png.size() << " bytes";
    const auto first = frnn::sim::decode_png(slurp(dir / "rec" / "frame_00000.png"));
    EXPECT_NE(first.rgb, frame.rgb);  // the droplet fell: each frame is its own

    if (run_in(dir, "command -v ffmpeg").code != 0) GTEST_SKIP() << "ffmpeg is not installed: no MP4 to check";
    const auto probe = run_in(dir, "ffprobe -v error -select_streams v:0 -count_frames -show_entries "
                                   "stream=nb_read_frames,width,height -of json rec/recording.mp4");
    ASSERT_EQ(probe.code, 0) << probe.err;
    const auto stream = nlohmann::json::parse(probe.out).at("streams").at(0);
    EXPECT_EQ(stream.at("nb_read_frames"), "4");
    EXPECT_EQ(stream.at("width"), 960);
    EXPECT_EQ(stream.at("height"), 600);
}

// A second, shorter recording into the same folder: its MP4 holds its own frames only.
TEST(ViewerRecord, ShorterRecordingReplacesTheFramesOfALongerOne) {
    const scratch_dir dir("viewer_record_again");
    write_text(dir / "script.json", R"({"steps_per_frame": 1, "actions": [{"frame": 1, "do": "record", "dir": "rec"},
        {"frame": 5, "do": "stop_recording"}, {"frame": 6, "do": "record", "dir": "rec"}]})");
    const auto r = run_viewer(dir, "--scene droplet --dim 2 --particles 100 --script script.json --frames 8");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(std::filesystem::exists(dir / "rec" / "frame_00001.png"));   // frames 6 and 7
    EXPECT_FALSE(std::filesystem::exists(dir / "rec" / "frame_00002.png"));  // frames 3 and 4 of the first
    if (run_in(dir, "command -v ffmpeg").code != 0) GTEST_SKIP() << "ffmpeg is not installed: no MP4 to check";
    const auto probe = run_in(dir, "ffprobe -v error -select_streams v:0 -count_frames -show_entries stream=nb_read_frames "
                                   "-of json rec/recording.mp4");
    ASSERT_EQ(probe.code, 0) << probe.err;
    EXPECT_EQ(nlohmann::json::parse(probe.out).at("streams").at(0).at("nb_read_frames"), "2");
}
