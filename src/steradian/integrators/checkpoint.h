#pragma once
/// Checkpoint files: the state of an unfinished render or measurement, saved so that a
/// killed process loses at most the work since the last save, and `--resume` continues to
/// the same result bit for bit.
///
/// A checkpoint is a set of named sections, each text or raw bytes (numbers are written
/// as text that reads back to the same double; arrays as the host's bytes, which is why the
/// file records the byte order). The file is written atomically (write_file_atomically: a
/// reader sees the previous checkpoint or the new one, never a mix, after a kill at any
/// moment) and carries a hash of its contents, so a damaged file is an error, never a wrong
/// image. Its identity (`kind`, the build, the scene's contents and the options that decide
/// the result) is compared on resume, and a mismatch is refused with a message naming the
/// difference.
#include <cstdint>
#include <cstring>
#include <map>
#include <string>
#include <type_traits>
#include <vector>

#include "steradian/core/error.h"
#include "steradian/film/film.h"
#include "steradian/integrators/integrator.h"
#include "steradian/integrators/measure.h"

namespace sr {

class Checkpoint {
  public:
    /// Sections, by name (a name is one line: no '\n').
    void set(const std::string& key, std::string value) { m_sections[key] = std::move(value); }
    void set_number(const std::string& key, double v);
    void set_number(const std::string& key, uint64_t v);
    template <typename T>
    void set_array(const std::string& key, const std::vector<T>& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        std::string bytes(v.size() * sizeof(T), '\0');
        if (!v.empty()) std::memcpy(bytes.data(), v.data(), bytes.size());
        m_sections[key] = std::move(bytes);
    }

    bool has(const std::string& key) const { return m_sections.count(key) != 0; }
    /// The section `key`; throws sr::Error naming the file if it is missing.
    const std::string& get(const std::string& key) const;
    double get_double(const std::string& key) const;
    uint64_t get_u64(const std::string& key) const;
    /// An array of exactly `count` elements; throws sr::Error otherwise.
    template <typename T>
    std::vector<T> get_array(const std::string& key, size_t count) const {
        static_assert(std::is_trivially_copyable_v<T>);
        const std::string& bytes = get(key);
        if (bytes.size() != count * sizeof(T))
            throw size_error(key, bytes.size(), count * sizeof(T));
        std::vector<T> v(count);
        if (count) std::memcpy(v.data(), bytes.data(), bytes.size());
        return v;
    }

    /// Writes the checkpoint to `path` atomically; throws sr::Error on any failure.
    void save(const std::string& path) const;
    /// Reads a checkpoint; throws sr::Error naming `path` unless it is a whole, undamaged
    /// checkpoint of this format version and byte order.
    static Checkpoint load(const std::string& path);
    /// The file it was loaded from ("" if built in memory).
    const std::string& path() const { return m_path; }

    /// Throws sr::Error unless section `key` equals `value`: "<file> was written for
    /// <what> <recorded>; this <kind> has <value>", with `hint` after it.
    void expect(const std::string& key, const std::string& value, const std::string& what,
                const std::string& hint = "") const;

  private:
    Error size_error(const std::string& key, size_t got, size_t want) const;
    std::string m_path;
    std::map<std::string, std::string> m_sections;
};

/// A render's state: the film's sums ("film") and the statistics of the work that made
/// them ("spp", "paths", ...).
void put_render_state(Checkpoint& c, const Film& film, const RenderStats& so_far);
/// Restores the film's sums from a checkpoint written for a film of the same size and
/// returns the statistics saved with them; throws sr::Error naming the file otherwise.
RenderStats get_render_state(const Checkpoint& c, Film& film);

/// A measurement's state (MeasureState), and back; get_measure_state throws sr::Error
/// naming the file unless the state has `values` values, consistently.
void put_measure_state(Checkpoint& c, const MeasureState& state);
MeasureState get_measure_state(const Checkpoint& c, size_t values);

/// A hash of the running executable's bytes: a checkpoint is resumed only by the build that
/// wrote it (another build may sample differently, and the result would not be the one
/// promised).
std::string executable_id();

/// A hash of the contents of every input file the process has read (input_files_read():
/// the scene, its includes, meshes, luminaires, spectra, images), independent of the order
/// they were read in and of where they are: the identity of a scene.
std::string inputs_digest();

}  // namespace sr
