#pragma once
/// MPI for the `steradian-mpi` command (docs/distributed.md): the one place that includes
/// <mpi.h>. It implements the library's Messenger (integrators/distributed.h) over
/// MPI_COMM_WORLD and the few collective steps the command needs around it.
#include <list>
#include <string>
#include <vector>

#include <mpi.h>

#include "steradian/integrators/distributed.h"

namespace sr::mpi {

/// MPI from construction (MPI_Init_thread, MPI_THREAD_FUNNELED: only the thread that made
/// the session calls MPI) to destruction (MPI_Finalize).
class Session final : public Messenger {
public:
    Session(int& argc, char**& argv);
    ~Session() override;
    Session(const Session&) = delete;
    Session& operator=(const Session&) = delete;

    int rank() const override { return m_rank; }
    int size() const override { return m_size; }
    void send(int to, const std::vector<char>& data) override;
    bool try_receive(std::vector<char>& data, int& from) override;

    /// Collective: the number of processes that pass `failed` = true.
    int count_failed(bool failed);
    /// Collective: process 0's `s` on every process.
    std::string broadcast(const std::string& s);
    /// Collective: the sum over processes of `v`, on process 0.
    double sum_to_root(double v);
    /// Ends every process of the job with `code` (MPI_Abort).
    [[noreturn]] void abort(int code);

private:
    /// Completes the sends that can be completed; with `all`, waits for every one.
    void progress_sends(bool all);
    int m_rank = 0, m_size = 1;
    /// Sends in flight, with their buffers: MPI_Isend, so that two processes sending each
    /// other large messages at once do not wait on each other (a blocking MPI_Send of a
    /// large message waits for the matching receive).
    struct Pending {
        std::vector<char> data;
        MPI_Request request;
    };
    std::list<Pending> m_sends;
};

}  // namespace sr::mpi
