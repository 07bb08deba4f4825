// The Python module `steradian` (pybind11): load a pbrt-v4 scene, render it to a numpy array,
// measure its meters. docs/python.md describes the interface; tests/python/ tests it.
//
//     import steradian
//     scene = steradian.load("scene.pbrt")            # or steradian.loads(text, base_dir=".")
//     img = scene.render(spp=64, seed=0, threads=0)   # H x W x 3 float32, linear, as the EXR
//     out = scene.render(spp=64, aov=True)            # {"rgb": ..., "Albedo": ..., ...}
//     r = scene.measure(rel_error=1e-3)               # the meters' JSON, with numpy arrays
//
// Rendering and measuring run on a worker thread with the GIL released; the calling thread
// wakes every 50 ms to check for Ctrl-C (PyErr_CheckSignals: Python runs signal handlers on
// the main thread only) and to report progress. Ctrl-C stops the work at the end of the pass
// in flight and raises KeyboardInterrupt.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "steradian/core/error.h"
#include "steradian/core/error_list.h"
#include "steradian/film/film.h"
#include "steradian/integrators/integrator.h"
#include "steradian/integrators/measure.h"
#include "steradian/scene/build.h"
#include "steradian/scene/pbrt/parser.h"

namespace py = pybind11;

namespace {

/// A loaded scene: built once, rendered or measured any number of times.
struct PyScene {
    sr::Scene scene;
    std::string name;
};

/// Runs `work` on a worker thread while this (Python) thread, without the GIL, wakes every
/// 50 ms to check for Ctrl-C and to call `tick` (with the GIL). On Ctrl-C `stop` is set, the
/// work ends at its next pass boundary, and KeyboardInterrupt is raised. An exception of the
/// work (an sr::Error) is rethrown here; so is one raised by `tick`.
template <typename Work, typename Tick>
void run_interruptibly(Work&& work, Tick&& tick, std::atomic<bool>& stop) {
    std::mutex mu;
    std::condition_variable cv;
    bool finished = false;
    std::exception_ptr failure;
    std::optional<py::error_already_set> python_error;
    {
        py::gil_scoped_release release;
        std::thread worker([&] {
            try {
                work();
            } catch (...) {
                failure = std::current_exception();
            }
            std::lock_guard<std::mutex> lock(mu);
            finished = true;
            cv.notify_all();
        });
        std::unique_lock<std::mutex> lock(mu);
        while (!finished) {
            cv.wait_for(lock, std::chrono::milliseconds(50));
            if (finished || python_error) continue;
            lock.unlock();
            {
                py::gil_scoped_acquire acquire;
                try {
                    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
                    tick();
                } catch (py::error_already_set& e) {
                    python_error.emplace(std::move(e));
                    stop = true;
                }
            }
            lock.lock();
        }
        lock.unlock();
        worker.join();
    }
    if (python_error) throw std::move(*python_error);
    if (failure) std::rethrow_exception(failure);
}

/// A progress reporter from the `progress` argument: None (nothing), a callable
/// progress(done, total), or True (tqdm if it can be imported, else a line on stderr).
struct Progress {
    py::object callback;
    py::object bar;  ///< a tqdm bar
    int shown = -1;
    Progress(const py::object& arg, int total, const char* what) {
        if (arg.is_none() || (py::isinstance<py::bool_>(arg) && !arg.cast<bool>())) return;
        if (py::isinstance<py::bool_>(arg)) {
            try {
                bar = py::module_::import("tqdm").attr("tqdm")(py::arg("total") = total,
                                                               py::arg("desc") = what);
            } catch (py::error_already_set&) {
                callback = py::module_::import("sys").attr("stderr").attr("write");
                callback = py::cpp_function([cb = callback, what](int done, int all) {
                    cb(py::str("\r{}: {}/{}").format(what, done, all));
                });
            }
        } else {
            callback = arg;
        }
    }
    void update(int done, int total) {
        if (done == shown) return;
        if (bar) bar.attr("update")(done - std::max(shown, 0));
        if (callback) callback(done, total);
        shown = done;
    }
    void close() {
        if (bar) bar.attr("close")();
    }
};

/// The image's channels [first, first + count) as an H x W x count float32 array (H x W
/// when count is 1).
py::array_t<float> channels_array(const sr::Image& img, int first, int count) {
    std::vector<py::ssize_t> shape{img.height, img.width};
    if (count > 1) shape.push_back(count);
    py::array_t<float> a(shape);
    float* out = a.mutable_data();
    const size_t n = size_t(img.width) * size_t(img.height);
    for (size_t i = 0; i < n; ++i)
        for (int c = 0; c < count; ++c)
            out[i * size_t(count) + size_t(c)] = img.data[i * size_t(img.channels) + size_t(first + c)];
    return a;
}

/// The layers of a film's output beyond R, G, B, by the EXR channel names' prefixes
/// ("Albedo.R" -> "Albedo"; "u" -> "u"), in file order: name -> (first channel, count).
std::vector<std::pair<std::string, std::pair<int, int>>> aov_layers(const sr::Image& img) {
    std::vector<std::pair<std::string, std::pair<int, int>>> layers;
    for (int c = 3; c < int(img.channel_names.size()); ++c) {
        const std::string& n = img.channel_names[size_t(c)];
        const std::string layer = n.substr(0, n.find('.'));
        if (!layers.empty() && layers.back().first == layer &&
            layers.back().second.first + layers.back().second.second == c)
            ++layers.back().second.second;
        else
            layers.push_back({layer, {c, 1}});
    }
    return layers;
}

py::object render(PyScene& self, int spp, uint64_t seed, int threads, double time,
                  const py::object& aov, const py::object& progress) {
    sr::Film film(self.scene.film);
    sr::RenderOptions ro;
    ro.spp = spp;
    ro.seed = seed;
    ro.threads = threads;
    ro.time_budget = time;
    std::atomic<bool> stop{false};
    ro.stop = &stop;
    const int total = sr::render_samples_per_pixel(self.scene, ro);
    std::atomic<int> done{0};
    Progress bar(progress, total, "steradian");
    // Passes sized to end about every quarter second, so that Ctrl-C (which waits for the
    // pass in flight) and progress answer promptly: any schedule of passes gives the same
    // image bit for bit (integrator.h, kPassAlign).
    ro.checkpoint_every = 0.25;
    ro.checkpoint = [&](const sr::RenderStats& so_far) { done = so_far.spp; };
    sr::RenderStats stats;
    run_interruptibly([&] { stats = sr::render(self.scene, film, ro); },
                      [&] { bar.update(done, total); }, stop);
    bar.update(stats.spp, total);
    bar.close();
    if (stats.nonfinite > 0)
        PyErr_WarnFormat(PyExc_RuntimeWarning, 1, "%llu samples were NaN or infinite and were zeroed",
                         static_cast<unsigned long long>(stats.nonfinite));

    const sr::Image img = film.output_image();
    py::array_t<float> rgb = channels_array(img, 0, 3);
    if (aov.is_none() || (py::isinstance<py::bool_>(aov) && !aov.cast<bool>())) return rgb;
    const auto layers = aov_layers(img);
    std::vector<std::string> wanted;
    if (py::isinstance<py::bool_>(aov)) {
        for (const auto& l : layers) wanted.push_back(l.first);
    } else if (py::isinstance<py::str>(aov)) {
        wanted.push_back(aov.cast<std::string>());
    } else {
        wanted = aov.cast<std::vector<std::string>>();
    }
    py::dict out;
    out["rgb"] = rgb;
    for (const std::string& w : wanted) {
        auto it = std::find_if(layers.begin(), layers.end(),
                               [&](const auto& l) { return l.first == w; });
        if (it == layers.end()) {
            std::string have;
            for (const auto& l : layers) have += (have.empty() ? "" : ", ") + l.first;
            throw py::value_error("no auxiliary channel \"" + w + "\" in this film's output (" +
                                  (have.empty() ? std::string("it has none: use Film \"gbuffer\" "
                                                              "or \"spectral\"")
                                                : "it has " + have) +
                                  ")");
        }
        out[py::str(w)] = channels_array(img, it->second.first, it->second.second);
    }
    return out;
}

py::object measure(PyScene& self, double rel_error, double time, int threads, uint64_t seed,
                   const py::object& progress) {
    if (self.scene.meters.empty())
        throw py::value_error("the scene " + self.name + " has no Meter directives to measure");
    sr::MeasureOptions mo;
    mo.rel_error = rel_error;
    mo.time_budget = time;
    mo.threads = threads;
    mo.seed = seed;
    std::atomic<bool> stop{false};
    mo.stop = &stop;
    std::atomic<int> rounds{0};
    Progress bar(progress, 0, "steradian measure");
    // Batches of work sized to end about every quarter second (Ctrl-C, progress); the
    // readings do not depend on the batches (measure.h).
    mo.checkpoint_every = 0.25;
    mo.checkpoint = [&](const sr::MeasureState&) { ++rounds; };
    sr::MeasureResult r;
    run_interruptibly([&] { r = sr::measure(self.scene, mo); },
                      [&] { bar.update(rounds, 0); }, stop);
    bar.close();
    // The JSON the command line writes, with the per-point lists as numpy arrays and grids'
    // values and standard errors also shaped nv x nu ("grid", "grid_stderr"; row by row
    // along u, as the JSON lists them).
    py::object np = py::module_::import("numpy");
    py::dict root = py::module_::import("json").attr("loads")(sr::meters_json(r));
    for (py::handle m : root["meters"]) {
        py::dict d = py::reinterpret_borrow<py::dict>(m);
        for (const char* k : {"values", "stderr", "samples", "converged", "points"})
            d[k] = np.attr("asarray")(d[k]);
        if (d.contains("resolution")) {
            py::list res = d["resolution"];
            py::tuple shape = py::make_tuple(res[1], res[0]);
            d["grid"] = d["values"].attr("reshape")(shape);
            d["grid_stderr"] = d["stderr"].attr("reshape")(shape);
        }
    }
    return root;
}

}  // namespace

PYBIND11_MODULE(steradian, m) {
    m.doc() = "steradian: a spectral, physically based renderer and lighting simulator that "
              "reads pbrt-v4 scenes (docs/python.md).";
    m.attr("__version__") = STERADIAN_VERSION;

    // Errors of scenes and options: a message, and the file, line and column it names.
    static py::exception<sr::Error> error(m, "Error", PyExc_RuntimeError);
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const sr::Error& e) {
            // A new instance of steradian.Error (calling the type; error(msg) would only set it).
            py::object ex = py::handle(error.ptr())(e.what());
            const std::vector<sr::ErrorEntry> entries = sr::error_entries(e);
            const sr::SourceLoc& loc = entries.empty() ? e.loc() : entries.front().loc;
            ex.attr("file") = loc.file.empty() ? py::object(py::none()) : py::str(loc.file);
            ex.attr("line") = loc.line;
            ex.attr("column") = loc.column;
            ex.attr("message") = entries.empty() ? e.message() : entries.front().message;
            py::list all;
            for (const sr::ErrorEntry& en : entries)
                all.append(py::make_tuple(en.loc.file, en.loc.line, en.loc.column, en.message));
            ex.attr("errors") = all;
            PyErr_SetObject(error.ptr(), ex.ptr());
        }
    });

    py::class_<PyScene>(m, "Scene", "A built scene: render() it, measure() its meters.")
        .def_property_readonly("resolution",
                               [](const PyScene& s) {
                                   return py::make_tuple(s.scene.film.width(),
                                                         s.scene.film.height());
                               },
                               "(width, height) of the film's image")
        .def_property_readonly("spp",
                               [](const PyScene& s) {
                                   return sr::render_samples_per_pixel(s.scene, {});
                               },
                               "the Sampler's samples per pixel")
        .def_property_readonly("meters",
                               [](const PyScene& s) {
                                   std::vector<std::string> names;
                                   for (const auto& mt : s.scene.meters) names.push_back(mt.name);
                                   return names;
                               },
                               "the names of the scene's Meter directives")
        .def("render", &render, py::arg("spp") = 0, py::arg("seed") = 0, py::arg("threads") = 0,
             py::arg("time") = 0.0, py::arg("aov") = py::none(), py::arg("progress") = py::none(),
             "Renders the image: an H x W x 3 float32 array (linear, the values the EXR holds).\n"
             "spp: samples per pixel (0: the scene's); seed: added to the sampler's seed;\n"
             "threads: 0 for all; time: a budget in seconds (0: none).\n"
             "aov: True, a name or a list of names of auxiliary channels (Film \"gbuffer\":\n"
             "Albedo, P, dzdx, dzdy, N, Ns, u, v, Variance; \"spectral\": its buckets): then a\n"
             "dict {\"rgb\": image, name: array}.\n"
             "progress: a callable progress(done_spp, total_spp), or True (tqdm if present).")
        .def("measure", &measure, py::arg("rel_error") = 1e-3, py::arg("time") = 0.0,
             py::arg("threads") = 0, py::arg("seed") = 0, py::arg("progress") = py::none(),
             "Measures the scene's meters to rel_error (or within the time budget): the dict the\n"
             "command line writes as JSON, with numpy arrays (grids also as 'grid' and\n"
             "'grid_stderr', nv x nu).");

    m.def(
        "load",
        [](const std::string& path) {
            auto s = std::make_unique<PyScene>();
            s->scene = sr::build_scene(sr::parse_pbrt_file(path));
            s->name = path;
            return s;
        },
        py::arg("path"), "Loads and builds a pbrt-v4 scene file.");
    m.def(
        "loads",
        [](const std::string& text, const std::string& base_dir, const std::string& name) {
            auto s = std::make_unique<PyScene>();
            s->scene = sr::build_scene(sr::parse_pbrt_string(text, name, base_dir));
            s->name = name;
            return s;
        },
        py::arg("text"), py::arg("base_dir") = ".", py::arg("name") = "<string>",
        "Loads and builds a pbrt-v4 scene given as text; files it names resolve against base_dir.");
}
