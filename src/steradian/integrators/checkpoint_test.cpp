#include "steradian/integrators/checkpoint.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

namespace sr {
namespace {

namespace fs = std::filesystem;

std::string temp_path(const std::string& name) {
    return (fs::temp_directory_path() / ("steradian-checkpoint-test-" + name)).string();
}

std::string read_all(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), {});
}

void write_all(const std::string& path, const std::string& s) {
    std::ofstream(path, std::ios::binary) << s;
}

TEST(Checkpoint, SectionsRoundTripBitForBit) {
    Checkpoint c;
    c.set("kind", "render");
    c.set("key with spaces", "value\nover lines\n");  // a key ends at its line's last space
    c.set("empty", "");
    // Doubles as text must read back to the same bits, extremes included.
    const double values[] = {0.1,
                             1.0 / 3.0,
                             std::numeric_limits<double>::denorm_min(),
                             std::numeric_limits<double>::max(),
                             -0.0,
                             6.02214076e23};
    for (int i = 0; i < 6; ++i) c.set_number("d" + std::to_string(i), values[i]);
    c.set_number("u", uint64_t(18446744073709551615ULL));
    std::vector<PixelSum> sums(5);
    for (int i = 0; i < 5; ++i)
        sums[size_t(i)] = {{i * 0.1, std::sqrt(double(i)), -1.0 / (i + 1)}, i / 7.0};
    c.set_array("film", sums);
    const std::string path = temp_path("roundtrip.ckpt");
    c.save(path);

    const Checkpoint r = Checkpoint::load(path);
    EXPECT_EQ(r.get("kind"), "render");
    EXPECT_EQ(r.get("key with spaces"), "value\nover lines\n");
    EXPECT_EQ(r.get("empty"), "");
    for (int i = 0; i < 6; ++i) {
        const double v = r.get_double("d" + std::to_string(i));
        EXPECT_EQ(std::memcmp(&v, &values[i], sizeof v), 0) << i;
    }
    EXPECT_EQ(r.get_u64("u"), 18446744073709551615ULL);
    const std::vector<PixelSum> back = r.get_array<PixelSum>("film", 5);
    EXPECT_EQ(std::memcmp(back.data(), sums.data(), sizeof(PixelSum) * 5), 0);
    EXPECT_THROW(r.get_array<PixelSum>("film", 4), Error);  // wrong size
    EXPECT_THROW(r.get("missing"), Error);
    EXPECT_THROW(r.get_u64("kind"), Error);  // not a number
    fs::remove(path);
}

TEST(Checkpoint, DamageOfAnyByteIsDetected) {
    Checkpoint c;
    c.set("kind", "measure");
    c.set_array("value", std::vector<double>{1, 2, 3, 4});
    const std::string path = temp_path("damage.ckpt");
    c.save(path);
    const std::string good = read_all(path);
    ASSERT_NO_THROW(Checkpoint::load(path));
    // Every single-bit flip and every truncation is refused with a message, never accepted.
    int refused = 0, tried = 0;
    for (size_t i = 0; i < good.size(); ++i) {
        std::string bad = good;
        bad[i] = char(bad[i] ^ 0x10);
        write_all(path, bad);
        ++tried;
        try {
            Checkpoint::load(path);
        } catch (const Error& e) {
            ++refused;
            EXPECT_NE(std::string(e.what()).find(path), std::string::npos);
        }
        write_all(path, good.substr(0, i));
        ++tried;
        try {
            Checkpoint::load(path);
        } catch (const Error&) {
            ++refused;
        }
    }
    EXPECT_EQ(refused, tried);
    fs::remove(path);
}

TEST(Checkpoint, ExpectNamesBothValues) {
    Checkpoint c;
    c.set("samples-per-pixel", "1024");
    try {
        c.expect("samples-per-pixel", "512", "samples per pixel", "resume with the same count");
        FAIL() << "a mismatch must throw";
    } catch (const Error& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("1024"), std::string::npos) << m;
        EXPECT_NE(m.find("512"), std::string::npos) << m;
        EXPECT_NE(m.find("resume with the same count"), std::string::npos) << m;
    }
    EXPECT_NO_THROW(c.expect("samples-per-pixel", "1024", "samples per pixel"));
}

TEST(Checkpoint, MeasureStateRoundTrip) {
    MeasureState s;
    s.round = 3;
    s.next_n = {0, 64, 128};
    s.values = {1.5, 2.25, 1e-300};
    s.stderrs = {0.1, 0.2, 0.3};
    s.samples = {32, 64, 2048};
    s.converged = {1, 0, 0};
    s.item_done = {1, 0, 1, 1};
    s.replica_mean = {0.5, 0, 0.25, 0.125};
    s.paths = 12345;
    s.rays = 67890;
    s.nonfinite = 2;
    s.wall_seconds = 1.25;
    s.cpu_seconds = 2.5;
    Checkpoint c;
    put_measure_state(c, s);
    const std::string path = temp_path("measure.ckpt");
    c.save(path);
    const MeasureState r = get_measure_state(Checkpoint::load(path), 3);
    EXPECT_EQ(r.round, 3);
    EXPECT_EQ(r.next_n, s.next_n);
    EXPECT_EQ(r.values, s.values);
    EXPECT_EQ(r.stderrs, s.stderrs);
    EXPECT_EQ(r.samples, s.samples);
    EXPECT_EQ(r.converged, s.converged);
    EXPECT_EQ(r.item_done, s.item_done);
    EXPECT_EQ(r.replica_mean, s.replica_mean);
    EXPECT_EQ(r.paths, s.paths);
    EXPECT_EQ(r.rays, s.rays);
    EXPECT_EQ(r.nonfinite, s.nonfinite);
    EXPECT_EQ(r.wall_seconds, s.wall_seconds);
    EXPECT_THROW(get_measure_state(Checkpoint::load(path), 4), Error);  // another scene's
    fs::remove(path);
}

}  // namespace
}  // namespace sr
