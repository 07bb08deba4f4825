#pragma once
/// The progress bar of renders (render.cpp, mlt/, sppm/): percent, elapsed, ETA on stderr.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <mutex>
#include <thread>

namespace sr {

/// Progress bar on stderr: percent, elapsed, ETA. Redrawn by its own thread.
class Progress {
public:
    Progress(bool enabled, uint64_t total) : m_enabled(enabled), m_total(total) {
        if (!m_enabled) return;
        m_start = std::chrono::steady_clock::now();
        m_thread = std::thread([this] { loop(); });
    }
    ~Progress() { finish(); }
    void add(uint64_t n) { m_done += n; }
    void finish() {
        if (!m_enabled || !m_thread.joinable()) return;
        {
            std::lock_guard lock(m_mutex);
            m_stop = true;
        }
        m_cv.notify_all();
        m_thread.join();
        draw();
        std::fprintf(stderr, "\n");
    }

private:
    void loop() {
        std::unique_lock lock(m_mutex);
        while (!m_stop) {
            m_cv.wait_for(lock, std::chrono::milliseconds(200));
            if (!m_stop) draw();
        }
    }
    void draw() {
        double frac = m_total ? double(m_done.load()) / double(m_total) : 1;
        frac = std::min(frac, 1.0);
        double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
        double eta = frac > 0 ? el * (1 - frac) / frac : 0;
        const int width = 40;
        int filled = int(frac * width);
        char bar[width + 1];
        for (int i = 0; i < width; ++i) bar[i] = i < filled ? '#' : '.';
        bar[width] = 0;
        std::fprintf(stderr, "\r[%s] %5.1f%%  elapsed %6.1fs  ETA %6.1fs ", bar, 100 * frac, el,
                     eta);
        std::fflush(stderr);
    }
    bool m_enabled;
    uint64_t m_total;
    std::atomic<uint64_t> m_done{0};
    std::chrono::steady_clock::time_point m_start;
    std::thread m_thread;
    std::mutex m_mutex;
    std::condition_variable m_cv;
    bool m_stop = false;
};

}  // namespace sr
