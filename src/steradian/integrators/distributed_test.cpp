// Distributed rendering and measuring without MPI: the coordinator and its workers are
// threads of this process, joined by in-process message queues. The determinism rule (same
// scene, seed and sample count: the same image and readings, whatever the split) is the
// oracle: the film's sums and the readings equal a one-process run's bit for bit.
#include "steradian/integrators/distributed.h"

#include <gtest/gtest.h>

#include <atomic>
#include <deque>
#include <mutex>
#include <thread>

#include "steradian/core/math.h"
#include "steradian/film/film.h"
#include "steradian/integrators/integrator.h"
#include "steradian/integrators/measure.h"
#include "steradian/integrators/radiosity/radiosity.h"
#include "steradian/scene/build.h"
#include "steradian/scene/pbrt/parser.h"
#include "steradian/scene/scene.h"

namespace sr {
namespace {

struct Hub {
    std::mutex mutex;
    std::vector<std::deque<std::pair<int, std::vector<char>>>> inbox;
    explicit Hub(int n) : inbox(size_t(n)) {}
};

class LocalMessenger final : public Messenger {
public:
    LocalMessenger(Hub& hub, int rank) : m_hub(hub), m_rank(rank) {}
    int rank() const override { return m_rank; }
    int size() const override { return int(m_hub.inbox.size()); }
    void send(int to, const std::vector<char>& data) override {
        std::lock_guard lock(m_hub.mutex);
        m_hub.inbox[size_t(to)].emplace_back(m_rank, data);
    }
    bool try_receive(std::vector<char>& data, int& from) override {
        std::lock_guard lock(m_hub.mutex);
        auto& q = m_hub.inbox[size_t(m_rank)];
        if (q.empty()) return false;
        from = q.front().first;
        data = std::move(q.front().second);
        q.pop_front();
        return true;
    }

private:
    Hub& m_hub;
    int m_rank;
};

// A lit sphere over a floor, with a crop window (partial tiles), 72 spp (two passes), and a
// meter with indirect light (several rounds at 2 %).
Scene test_scene(const std::string& film, const std::string& integrator = "") {
    const std::string pbrt = integrator + R"(
LookAt 0 1 -4  0 0.5 0  0 1 0
Camera "perspective" "float fov" [ 45 ]
Film ")" + film + R"(" "integer xresolution" [ 37 ] "integer yresolution" [ 29 ]
     "float cropwindow" [ 0.1 0.9 0 1 ]
Sampler "zsobol" "integer pixelsamples" [ 72 ]
WorldBegin
AttributeBegin
  Translate 1 3 -1
  AreaLightSource "diffuse" "rgb L" [ 8 8 8 ]
  Shape "sphere" "float radius" [ 0.4 ]
AttributeEnd
Material "diffuse" "rgb reflectance" [ 0.6 0.5 0.4 ]
Shape "trianglemesh" "point3 P" [ -4 0 -4  4 0 -4  4 0 4  -4 0 4 ] "integer indices" [ 0 1 2 0 2 3 ]
Shape "sphere" "float radius" [ 0.7 ]
Meter "illuminance" "string name" "floor" "point3 p" [ 1.5 0 0  -1.5 0 0 ] "normal n" [ 0 1 0 ]
)";
    return build_scene(parse_pbrt_string(pbrt, "<test>", "."), BuildOptions{});
}

// Runs `coordinate(coordinator)` on this thread with `workers` worker threads.
// Each worker solves the radiosity system itself when `radiosity` (as steradian-mpi's do).
template <class F>
void with_workers(const Scene& scene, int workers, F&& coordinate, bool radiosity = false) {
    Hub hub(workers + 1);
    std::vector<std::thread> threads;
    for (int w = 1; w <= workers; ++w)
        threads.emplace_back([&hub, &scene, w, radiosity] {
            LocalMessenger m(hub, w);
            std::unique_ptr<RadiositySolution> sol;
            if (radiosity) sol = solve_radiosity(scene, scene.integrator.radiosity, 1);
            serve_work(m,
                       {render_job_handler(scene, 1, sol.get()),
                        measure_job_handler(scene, 1, sol.get()), mlt_job_handler(scene, 1),
                        sppm_job_handler(scene, 1), vcm_job_handler(scene, 1)},
                       2);
        });
    {
        LocalMessenger m(hub, 0);
        WorkCoordinator coord(m);
        coordinate(coord);
        coord.finish();
    }
    for (std::thread& t : threads) t.join();
}

void expect_same_render(const std::string& film_type, const RenderOptions& base,
                        const std::string& integrator = "") {
    const Scene scene = test_scene(film_type, integrator);
    const bool radiosity = scene.integrator.type == "radiosity";
    std::unique_ptr<RadiositySolution> sol;
    if (radiosity) sol = solve_radiosity(scene, scene.integrator.radiosity, 2);
    Film one(scene.film);
    RenderOptions ro = base;
    ro.threads = 2;
    ro.radiosity = sol.get();
    const RenderStats s1 = render(scene, one, ro);
    for (int workers : {1, 2}) {
        Film many(scene.film);
        with_workers(
            scene, workers,
            [&](WorkCoordinator& coord) {
                RenderOptions rd = base;
                rd.threads = 1;
                rd.distribute = &coord;
                rd.radiosity = sol.get();
                const RenderStats s = render(scene, many, rd);
                EXPECT_EQ(s.spp, s1.spp);
                EXPECT_EQ(s.camera_paths, s1.camera_paths);
                EXPECT_EQ(s.rays, s1.rays);
                ASSERT_EQ(s.strategy_images.size(), s1.strategy_images.size());
                for (size_t k = 0; k < s1.strategy_images.size(); ++k)
                    EXPECT_EQ(s.strategy_images[k].second.data, s1.strategy_images[k].second.data)
                        << s1.strategy_images[k].first;
            },
            radiosity);
        EXPECT_EQ(many.splat_sums(), one.splat_sums()) << integrator;  // bdpt, lightpath
        EXPECT_EQ(many.rgb_image().data, one.rgb_image().data) << integrator;
        ASSERT_EQ(many.sums().size(), one.sums().size());
        for (size_t i = 0; i < one.sums().size(); ++i) {
            for (int c = 0; c < 3; ++c)
                ASSERT_EQ(many.sums()[i].xyz[c], one.sums()[i].xyz[c]) << film_type << " pixel " << i;
            ASSERT_EQ(many.sums()[i].weight, one.sums()[i].weight);
        }
        EXPECT_EQ(many.aux_sums(), one.aux_sums()) << film_type;
    }
}

TEST(Distributed, RenderEqualsOneProcessBitForBit) {
    expect_same_render("rgb", {});
    expect_same_render("gbuffer", {});  // auxiliary channels travel with the tiles
}

TEST(Distributed, SplattingIntegratorsEqualOneProcessBitForBit) {
    // Their splats land in any pixel; reduced in tile order whoever rendered the tiles.
    expect_same_render("rgb", {}, R"(Integrator "bdpt" "integer maxdepth" [ 4 ])");
    expect_same_render("rgb", {}, R"(Integrator "lightpath" "integer maxdepth" [ 4 ])");
    // visualizestrategies: the strategy images' splats travel too.
    expect_same_render("rgb", {},
                       R"(Integrator "bdpt" "integer maxdepth" [ 2 ] "bool visualizestrategies" true)");
}

TEST(Distributed, MetropolisEqualsOneProcessBitForBit) {
    // The bootstrap's blocks (3 of 1,024 samples) and the chains travel between processes,
    // in blocks of 18 (1 worker) or 12 (2 workers) chains; the chains' splats are added in
    // chain order: the same splat sums, whatever the blocks. 3 rounds.
    RenderOptions ro;
    ro.spp = 3;
    expect_same_render("rgb", ro,
                       R"(Integrator "mlt" "integer maxdepth" [ 4 ] "integer bootstrapsamples" [ 600 ]
                          "integer chains" [ 300 ])");
}

TEST(Distributed, SppmEqualsOneProcessBitForBit) {
    // The photon chunks (5 of 1,024 photons) are traced by any process, gathered against the
    // coordinator's visible points and added in chunk order: the same pixels. 3 iterations.
    RenderOptions ro;
    ro.spp = 3;
    expect_same_render("rgb", ro,
                       R"(Integrator "sppm" "float radius" [ 0.1 ] "integer photonsperiteration" [ 5000 ])");
}

TEST(Distributed, RadiosityEqualsOneProcessBitForBit) {
    // Every process solves the same system (deterministic whatever the threads); the final
    // gather's tiles are shared as the path tracer's are.
    expect_same_render("rgb", {}, R"(Integrator "radiosity")");
}

TEST(Distributed, PacedPassesEqualOneProcess) {
    // Checkpoint-paced passes (8, 16, 32, 16 spp) shared among processes: the same image.
    RenderOptions ro;
    int calls = 0;
    ro.checkpoint = [&](const RenderStats&) { ++calls; };
    expect_same_render("rgb", ro);
    EXPECT_GT(calls, 2);
}

TEST(Distributed, MeasureEqualsOneProcessBitForBit) {
    const Scene scene = test_scene("rgb");
    MeasureOptions mo;
    mo.rel_error = 0.02;
    mo.threads = 2;
    const MeasureResult one = measure(scene, mo);
    // More rounds than the pilot: every value's pilot is 32 replicas x 32 samples.
    uint64_t pilots = 0;
    for (const MeterReading& r : one.readings) pilots += uint64_t(32 * 32) * r.values.size();
    ASSERT_GT(one.paths, pilots);
    for (int workers : {1, 2}) {
        with_workers(scene, workers, [&](WorkCoordinator& coord) {
            MeasureOptions md = mo;
            md.threads = 1;
            md.distribute = &coord;
            const MeasureResult many = measure(scene, md);
            EXPECT_EQ(many.readings[0].values, one.readings[0].values);
            EXPECT_EQ(many.readings[0].stderrs, one.readings[0].stderrs);
            EXPECT_EQ(many.readings[0].samples, one.readings[0].samples);
            EXPECT_EQ(many.paths, one.paths);
        });
    }
}

// The splat hook: whoever computed an item, Phase::reduce is called for items 0, 1, ... (once
// the phase is complete, or with a window as the completed items form a prefix), so an
// order-dependent sum is the one-process sum; with a window, no item is handed out (to a
// worker or to the coordinator's own threads) at or beyond the first unreduced + window.
void expect_reduce_in_item_order(size_t window) {
    Hub hub(3);
    const JobHandler square = [](ByteReader&, size_t count, ByteReader& in, ByteWriter& out) {
        for (size_t j = 0; j < count; ++j) {
            const uint64_t item = in.get<uint64_t>();
            const double x = in.get<double>();
            out.put(item);
            out.put(x * x);
        }
    };
    std::vector<std::thread> workers;
    for (int w = 1; w <= 2; ++w)
        workers.emplace_back([&hub, &square, w] {
            LocalMessenger m(hub, w);
            serve_work(m, {nullptr, nullptr, square}, 3);
        });
    LocalMessenger m(hub, 0);
    WorkCoordinator coord(m);
    const size_t n = 200;
    std::vector<double> terms(n, -1);
    std::vector<size_t> order;
    std::atomic<size_t> reduced{0}, beyond{0};
    auto handed_out = [&](size_t i) {
        if (window > 0 && i >= reduced.load() + window) ++beyond;
    };
    WorkCoordinator::Phase ph;
    ph.kind = 2;
    ph.items = n;
    ph.window = window;
    ph.input = [&](size_t i, ByteWriter& bw) {
        handed_out(i);
        bw.put(0.1 * double(i));
    };
    ph.output = [&](size_t i, ByteReader& br) { terms[i] = br.get<double>(); };
    ph.local = [&](const std::function<std::optional<size_t>()>& claim,
                   const std::function<void(size_t)>& done) {
        while (const std::optional<size_t> i = claim()) {
            handed_out(*i);
            terms[*i] = sqr(0.1 * double(*i));
            done(*i);
        }
    };
    double sum = 0;
    ph.reduce = [&](size_t i) {
        order.push_back(i);
        sum += terms[i];
        ++reduced;
    };
    ASSERT_TRUE(coord.run(ph));
    coord.finish();
    for (std::thread& t : workers) t.join();
    double expected = 0;
    for (size_t i = 0; i < n; ++i) expected += sqr(0.1 * double(i));
    ASSERT_EQ(order.size(), n);
    for (size_t i = 0; i < n; ++i) EXPECT_EQ(order[i], i);
    EXPECT_EQ(sum, expected);  // the same terms added in the same order: the same bits
    EXPECT_EQ(beyond.load(), 0u) << "items handed out beyond the window";
}

TEST(Distributed, RadiosityMeasureEqualsOneProcessBitForBit) {
    const Scene scene = test_scene("rgb", R"(Integrator "radiosity")");
    const auto sol = solve_radiosity(scene, scene.integrator.radiosity, 2);
    MeasureOptions mo;
    mo.rel_error = 0.02;
    mo.threads = 2;
    mo.radiosity = sol.get();
    const MeasureResult one = measure(scene, mo);
    ASSERT_EQ(one.method, "radiosity");
    for (int workers : {1, 2}) {
        with_workers(
            scene, workers,
            [&](WorkCoordinator& coord) {
                MeasureOptions md = mo;
                md.threads = 1;
                md.distribute = &coord;
                const MeasureResult many = measure(scene, md);
                EXPECT_EQ(many.readings[0].values, one.readings[0].values);
                EXPECT_EQ(many.readings[0].stderrs, one.readings[0].stderrs);
                EXPECT_EQ(many.readings[0].samples, one.readings[0].samples);
                EXPECT_EQ(many.paths, one.paths);
            },
            true);
    }
}

TEST(Distributed, ReduceSeesEveryItemInItemOrder) { expect_reduce_in_item_order(0); }

TEST(Distributed, WindowedReduceKeepsItemOrderAndTheWindow) {
    expect_reduce_in_item_order(5);
    expect_reduce_in_item_order(1);  // one item at a time: no deadlock, the same order
}

TEST(Distributed, ByteReaderRefusesATruncatedMessage) {
    std::vector<char> buf;
    ByteWriter(buf).put(uint32_t(7));
    ByteReader r(buf.data(), buf.size());
    EXPECT_EQ(r.get<uint32_t>(), 7u);
    EXPECT_THROW(r.get<uint8_t>(), Error);
}

}  // namespace
}  // namespace sr
