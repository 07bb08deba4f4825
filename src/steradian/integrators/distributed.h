#pragma once
/// Work shared between processes (MPI ranks; docs/distributed.md), without MPI: the library
/// sees only a `Messenger` that carries byte messages between numbered processes, which the
/// caller implements (src/mpi/ with MPI; a test with in-process queues).
///
/// Process 0, the coordinator, runs render() or measure() as a single process would and holds
/// every result (the film, the replica means). Its work is split into phases (a pass of
/// render(), a batch of a round of measure()) of numbered items (a tile, a (value, replica)
/// pair). The coordinator hands a phase's items out dynamically, a few at a time, to the other
/// processes (the workers, which request work as they become free) and to its own threads,
/// from one queue, so that a slow process takes fewer items and holds no one up. An item's
/// output is a pure function of its input (for a tile: its pixels' sums so far, which the
/// output continues), so every item is computed exactly as the single process computes it,
/// and the results do not depend on the number of processes, nor on who computed what.
///
/// Order-dependent reductions (the splats of a splatting integrator: bdpt, lightpath) keep
/// each item's contribution apart and add them in item order (Phase::reduce), the order a
/// single process uses, as the completed items form a prefix; a window bounds how many items
/// may be kept apart at once (Phase::window); see docs/distributed.md.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <functional>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include <tbb/task_arena.h>

namespace sr {

/// Byte messages between the processes of a distributed computation. Messages from one
/// process to another arrive in the order sent (MPI's non-overtaking rule).
class Messenger {
public:
    virtual ~Messenger() = default;
    virtual int rank() const = 0;  ///< this process, 0 .. size() - 1
    virtual int size() const = 0;
    /// Sends `data` to process `to` without waiting for it to be received (so that two
    /// processes may send each other large messages at once).
    virtual void send(int to, const std::vector<char>& data) = 0;
    /// A message from any process, if one has arrived: true, with its sender in `from`.
    virtual bool try_receive(std::vector<char>& data, int& from) = 0;
};

/// Appends trivially copyable values to a message.
class ByteWriter {
public:
    explicit ByteWriter(std::vector<char>& out) : m_out(out) {}
    template <class T>
    void put(const T& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        put_bytes(&v, sizeof v);
    }
    template <class T>
    void put_array(const T* v, size_t n) {
        static_assert(std::is_trivially_copyable_v<T>);
        put_bytes(v, n * sizeof(T));
    }
    void put_bytes(const void* p, size_t n) {
        const size_t at = m_out.size();
        m_out.resize(at + n);
        if (n) std::memcpy(m_out.data() + at, p, n);
    }
    size_t size() const { return m_out.size(); }
    std::vector<char>& buffer() { return m_out; }

private:
    std::vector<char>& m_out;
};

/// Reads what a ByteWriter wrote; throws sr::Error past the end (a malformed message).
class ByteReader {
public:
    ByteReader(const char* data, size_t size) : m_p(data), m_end(data + size) {}
    template <class T>
    T get() {
        static_assert(std::is_trivially_copyable_v<T>);
        T v;
        get_bytes(&v, sizeof v);
        return v;
    }
    template <class T>
    void get_array(T* v, size_t n) {
        static_assert(std::is_trivially_copyable_v<T>);
        get_bytes(v, n * sizeof(T));
    }
    void get_bytes(void* p, size_t n);
    /// The next n bytes as a reader of their own.
    ByteReader sub(size_t n);
    size_t left() const { return size_t(m_end - m_p); }

private:
    const char* m_p;
    const char* m_end;
};

/// The usual body of a Phase::local: `threads` threads of `arena` each claim items and call
/// `work(item)` until `claim` has none left or `stop()` is true.
void run_local_share(tbb::task_arena& arena, int threads,
                     const std::function<std::optional<size_t>()>& claim,
                     const std::function<bool()>& stop, const std::function<void(size_t)>& work);

/// The coordinator's side (process 0): runs phases, then ends the session.
class WorkCoordinator {
public:
    explicit WorkCoordinator(Messenger& m) : m_msg(m) {}
    ~WorkCoordinator();
    WorkCoordinator(const WorkCoordinator&) = delete;
    WorkCoordinator& operator=(const WorkCoordinator&) = delete;

    struct Phase {
        uint8_t kind = 0;            ///< which worker handler computes the items
        std::vector<char> header;    ///< sent with every job of the phase (the pass, ...)
        size_t items = 0;
        /// Item i's input, appended to a job for a worker.
        std::function<void(size_t item, ByteWriter&)> input;
        /// A worker's output of item i (called on the coordinator's thread, in arrival order).
        std::function<void(size_t item, ByteReader&)> output;
        /// The coordinator's own share: called once, on a thread of its own, with a function
        /// that claims the next item (nullopt: none left; with a window, it waits while the
        /// window is full) and one that reports a claimed item's output complete (needed
        /// with a window, else ignored); it returns when it gets nullopt.
        std::function<void(const std::function<std::optional<size_t>()>& claim,
                           const std::function<void(size_t item)>& done)>
            local;
        /// Polled between messages: true abandons the phase (no further items are handed out;
        /// outputs still in flight are dropped when they arrive).
        std::function<bool()> abandon;
        /// Called for every item in item order, on the coordinator's thread: the place for
        /// reductions whose result depends on the order of their terms (splats), which must
        /// keep each item's terms apart until then. Without a window, once the phase is
        /// complete (not when abandoned); with one, as soon as items 0 .. i are all complete
        /// (an abandoned phase may then have reduced some of its items: drop the result).
        std::function<void(size_t item)> reduce;
        /// With `reduce`: when > 0, at most this many items beyond the first one not yet
        /// reduced are handed out (to workers and to `local`), which bounds the memory of the
        /// terms kept apart; it should exceed the items all processes compute at once.
        size_t window = 0;
    };

    /// Runs a phase to completion (true) or until `abandon` (false).
    bool run(const Phase& phase);
    /// Ends the session: every worker's serve() returns. Called by the destructor if not before.
    void finish();
    int workers() const { return m_msg.size() - 1; }
    /// The workers' CPU time (user + system), known once finish() has returned.
    double workers_cpu_seconds() const { return m_workers_cpu; }

private:
    Messenger& m_msg;
    uint32_t m_phase = 0;
    std::vector<int> m_waiting;  ///< capacity of each worker's pending request (0: none)
    bool m_finished = false;
    double m_workers_cpu = 0;
};

/// A worker's computation of one job: `header` is the phase's, `inputs` holds `count` items
/// (each: u64 item number, then its input as the coordinator's Phase::input wrote it); writes
/// each item's output, in the same order, with ByteWriter (item number first, as read).
using JobHandler = std::function<void(ByteReader& header, size_t count, ByteReader& inputs,
                                      ByteWriter& outputs)>;

/// The worker's side (processes 1 .. size - 1): requests work, computes it with `handlers`
/// (indexed by Phase::kind; null: not available here), until the coordinator ends the
/// session. `capacity`: the most items to take at a time (a few per thread).
void serve_work(Messenger& m, const std::vector<JobHandler>& handlers, int capacity);

/// Phase kinds.
inline constexpr uint8_t kRenderTiles = 0;
inline constexpr uint8_t kMeasureItems = 1;
inline constexpr uint8_t kMltItems = 2;   ///< Integrator "mlt": bootstrap blocks, chains
inline constexpr uint8_t kSppmItems = 3;  ///< Integrator "sppm": photon chunks
/// Integrator "vcm": bands of film rows of an iteration's camera pass (vcm.cpp).
inline constexpr uint8_t kVcmItems = 4;

class Scene;
class RadiositySolution;
/// The worker handler of render()'s tiles and of measure()'s items for `scene`, with
/// `threads` worker threads (0: all); defined in render.cpp and measure.cpp. `radiosity`:
/// the scene's radiosity solution, which this process solved as the coordinator did (the
/// same solution: solve_radiosity is deterministic), for passes and rounds of the radiosity
/// method (null: none here; such a job is an error).
JobHandler render_job_handler(const Scene& scene, int threads,
                              const RadiositySolution* radiosity = nullptr);
JobHandler measure_job_handler(const Scene& scene, int threads,
                               const RadiositySolution* radiosity = nullptr);

/// The worker handlers of Integrator "mlt" (its bootstrap blocks and chains; mlt.cpp) and
/// of Integrator "sppm" (its photon chunks; sppm.cpp) for `scene`, with `threads` threads.
JobHandler mlt_job_handler(const Scene& scene, int threads);
JobHandler sppm_job_handler(const Scene& scene, int threads);
/// The worker handler of Integrator "vcm"'s camera passes (vcm.cpp) for `scene`, with
/// `threads` worker threads (0: all).
JobHandler vcm_job_handler(const Scene& scene, int threads);

/// A test hook (docs/distributed.md, "A rank that dies"): when the environment variable
/// STERADIAN_TEST_ABORT_AFTER_JOBS is N > 0, a worker aborts (SIGABRT) after N jobs.
int test_abort_after_jobs();

}  // namespace sr
