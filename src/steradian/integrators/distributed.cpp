#include "steradian/integrators/distributed.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <memory>
#include <thread>
#include <utility>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "steradian/core/error.h"
#include "steradian/integrators/integrator.h"

namespace sr {

void run_local_share(tbb::task_arena& arena, int threads,
                     const std::function<std::optional<size_t>()>& claim,
                     const std::function<bool()>& stop, const std::function<void(size_t)>& work) {
    arena.execute([&] {
        tbb::parallel_for(
            0, threads,
            [&](int) {
                while (!stop()) {
                    const std::optional<size_t> i = claim();
                    if (!i) return;
                    work(*i);
                }
            },
            tbb::simple_partitioner());
    });
}

namespace {

// Message types (the first byte of every message).
enum : uint8_t {
    kRequest = 1,   // worker -> coordinator: i32 capacity (the most items it wants)
    kResult = 2,    // worker -> coordinator: u32 phase, u32 count, outputs
    kFinished = 3,  // worker -> coordinator: f64 its CPU seconds; its last message
    kJob = 4,       // coordinator -> worker: u8 kind, u32 phase, u32 header size, header,
                    //                        u32 count, inputs
    kEnd = 5,       // coordinator -> worker: the session is over
};

/// Waiting for a message sleeps this long between polls, so that a waiting process leaves
/// its core to the computing ones (MPI's blocking calls spin).
constexpr auto kPoll = std::chrono::microseconds(200);

std::vector<char> message(uint8_t type) { return std::vector<char>(1, char(type)); }

}  // namespace

void ByteReader::get_bytes(void* p, size_t n) {
    if (n > left()) throw Error("distributed: a truncated message");
    if (n) std::memcpy(p, m_p, n);
    m_p += n;
}

ByteReader ByteReader::sub(size_t n) {
    if (n > left()) throw Error("distributed: a truncated message");
    ByteReader r(m_p, n);
    m_p += n;
    return r;
}

int test_abort_after_jobs() {
    const char* s = std::getenv("STERADIAN_TEST_ABORT_AFTER_JOBS");
    return s ? std::atoi(s) : 0;
}

WorkCoordinator::~WorkCoordinator() {
    try {
        finish();
    } catch (...) {
        // A destructor must not throw; a failure to reach a worker ends the job anyway.
    }
}

bool WorkCoordinator::run(const Phase& ph) {
    ++m_phase;
    const int nproc = m_msg.size();
    m_waiting.resize(size_t(nproc), 0);
    const size_t n = ph.items;
    // With a window, items are reduced as the completed ones form a prefix (`reduced` of
    // them so far), and none is handed out at or beyond reduced + window.
    const bool windowed = ph.reduce && ph.window > 0;
    std::unique_ptr<std::atomic<uint8_t>[]> complete;
    if (windowed) {
        complete.reset(new std::atomic<uint8_t>[n]);
        for (size_t i = 0; i < n; ++i) complete[i].store(0, std::memory_order_relaxed);
    }
    std::atomic<size_t> reduced{0};
    auto limit = [&] {
        return windowed ? std::min(n, reduced.load(std::memory_order_acquire) + ph.window) : n;
    };
    std::atomic<size_t> next{0};
    std::atomic<bool> stop{false};
    std::atomic<bool> local_done{!ph.local};
    // Takes up to `want` consecutive items below the limit: {first, count}; count 0: none now.
    auto take = [&](size_t want) -> std::pair<size_t, size_t> {
        size_t at = next.load();
        for (;;) {
            const size_t lim = limit();
            if (at >= lim) return {at, 0};
            const size_t k = std::min(want, lim - at);
            if (next.compare_exchange_weak(at, at + k)) return {at, k};
        }
    };
    auto claim = [&]() -> std::optional<size_t> {
        for (;;) {
            if (stop.load(std::memory_order_relaxed)) return std::nullopt;
            const auto [i, k] = take(1);
            if (k == 1) return i;
            if (i >= n) return std::nullopt;
            std::this_thread::sleep_for(kPoll);  // the window is full: wait for the reduction
        }
    };
    auto done = [&](size_t i) {
        if (windowed && i < n) complete[i].store(1, std::memory_order_release);
    };
    std::thread local;
    if (ph.local)
        local = std::thread([&] {
            ph.local(claim, done);
            local_done = true;
        });
    auto join_local = [&] {
        if (local.joinable()) local.join();
    };

    size_t outstanding = 0;  // items handed to workers whose outputs have not come back
    std::vector<char> msg;
    int from = -1;
    try {
        for (;;) {
            // Hand items to the workers waiting for them: guided chunks, shrinking as the phase
            // ends, so that the last items are spread out.
            for (int w = 1; w < nproc && !stop; ++w) {
                const int cap = m_waiting[size_t(w)];
                if (cap <= 0) continue;
                const size_t at = next.load();
                if (at >= n) break;
                const size_t left = n - at;
                const size_t want = std::clamp<size_t>(
                    (left + 2 * size_t(nproc) - 1) / (2 * size_t(nproc)), 1, size_t(cap));
                const auto [first, k] = take(want);
                if (k == 0) break;
                std::vector<char> job = message(kJob);
                ByteWriter bw(job);
                bw.put(ph.kind);
                bw.put(m_phase);
                bw.put(uint32_t(ph.header.size()));
                bw.put_bytes(ph.header.data(), ph.header.size());
                bw.put(uint32_t(k));
                for (size_t i = first; i < first + k; ++i) {
                    bw.put(uint64_t(i));
                    ph.input(i, bw);
                }
                m_msg.send(w, job);
                m_waiting[size_t(w)] = 0;
                outstanding += k;
            }
            bool progressed = false;
            if (windowed && !stop) {
                size_t r = reduced.load(std::memory_order_relaxed);
                while (r < n && complete[r].load(std::memory_order_acquire)) {
                    ph.reduce(r);
                    reduced.store(++r, std::memory_order_release);
                    progressed = true;
                }
            }
            if (m_msg.try_receive(msg, from)) {
                ByteReader br(msg.data(), msg.size());
                const uint8_t type = br.get<uint8_t>();
                if (from <= 0 || from >= nproc)
                    throw Error(fmt::format("distributed: a message from process {}", from));
                if (type == kRequest) {
                    m_waiting[size_t(from)] = std::max(1, br.get<int32_t>());
                } else if (type == kResult) {
                    const uint32_t phase = br.get<uint32_t>();
                    const uint32_t count = br.get<uint32_t>();
                    if (phase != m_phase) continue;  // of an abandoned phase
                    for (uint32_t j = 0; j < count; ++j) {
                        const uint64_t item = br.get<uint64_t>();
                        if (item >= n) throw Error("distributed: an output of no item");
                        ph.output(size_t(item), br);
                        done(size_t(item));
                    }
                    outstanding -= count;
                } else {
                    throw Error(fmt::format("distributed: unexpected message {} from process {}",
                                            int(type), from));
                }
                continue;
            }
            if (!stop && ph.abandon && ph.abandon()) stop = true;
            if (stop) break;
            if (local_done && outstanding == 0 && next.load() >= n) break;
            if (!progressed) std::this_thread::sleep_for(kPoll);
        }
    } catch (...) {
        stop = true;
        join_local();
        throw;
    }
    join_local();
    if (stop) return false;
    if (ph.reduce)
        for (size_t i = reduced.load(); i < n; ++i) ph.reduce(i);
    return true;
}

void WorkCoordinator::finish() {
    if (m_finished) return;
    m_finished = true;
    const int nproc = m_msg.size();
    for (int w = 1; w < nproc; ++w) m_msg.send(w, message(kEnd));
    // Every message a worker sent before its last is received (and dropped), so that none
    // waits for a receive that never comes.
    int finished = 0;
    std::vector<char> msg;
    int from = -1;
    while (finished < nproc - 1) {
        if (!m_msg.try_receive(msg, from)) {
            std::this_thread::sleep_for(kPoll);
            continue;
        }
        ByteReader br(msg.data(), msg.size());
        if (br.get<uint8_t>() != kFinished) continue;
        m_workers_cpu += br.get<double>();
        ++finished;
    }
}

void serve_work(Messenger& m, const std::vector<JobHandler>& handlers, int capacity) {
    auto request = [&] {
        std::vector<char> r = message(kRequest);
        ByteWriter(r).put(int32_t(std::max(1, capacity)));
        m.send(0, r);
    };
    request();
    const int abort_after = test_abort_after_jobs();
    int jobs = 0;
    std::vector<char> msg, out;
    int from = -1;
    for (;;) {
        if (!m.try_receive(msg, from)) {
            std::this_thread::sleep_for(kPoll);
            continue;
        }
        if (from != 0) throw Error(fmt::format("distributed: a message from process {}", from));
        ByteReader br(msg.data(), msg.size());
        const uint8_t type = br.get<uint8_t>();
        if (type == kEnd) {
            std::vector<char> fin = message(kFinished);
            ByteWriter(fin).put(process_cpu_seconds());
            m.send(0, fin);
            return;
        }
        if (type != kJob) throw Error(fmt::format("distributed: unexpected message {}", int(type)));
        // The next job is requested before this one is computed, so that it is there when
        // this one is done.
        request();
        const uint8_t kind = br.get<uint8_t>();
        const uint32_t phase = br.get<uint32_t>();
        ByteReader header = br.sub(br.get<uint32_t>());
        const uint32_t count = br.get<uint32_t>();
        if (kind >= handlers.size() || !handlers[kind])
            throw Error(fmt::format("distributed: no handler of work of kind {}", int(kind)));
        out = message(kResult);
        ByteWriter bw(out);
        bw.put(phase);
        bw.put(count);
        handlers[kind](header, count, br, bw);
        if (abort_after > 0 && ++jobs >= abort_after) {
            std::fprintf(stderr, "steradian: STERADIAN_TEST_ABORT_AFTER_JOBS: process %d aborts\n",
                         m.rank());
            std::abort();
        }
        m.send(0, out);
    }
}

}  // namespace sr
