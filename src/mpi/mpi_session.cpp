#include "mpi/mpi_session.h"

#include <climits>
#include <cstdlib>
#include <cstdio>

#include <fmt/format.h>

#include "steradian/core/error.h"

namespace sr::mpi {

namespace {

constexpr int kTag = 0x5354;  // the work messages' tag ("ST")

void check(int rc, const char* what) {
    if (rc != MPI_SUCCESS) {
        char msg[MPI_MAX_ERROR_STRING];
        int len = 0;
        MPI_Error_string(rc, msg, &len);
        throw Error(fmt::format("MPI: {} failed: {}", what, std::string(msg, size_t(len))));
    }
}

}  // namespace

Session::Session(int& argc, char**& argv) {
    int provided = 0;
    MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
    // Errors are returned, not fatal, so that they reach the user as messages.
    MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
    MPI_Comm_rank(MPI_COMM_WORLD, &m_rank);
    MPI_Comm_size(MPI_COMM_WORLD, &m_size);
    if (provided < MPI_THREAD_FUNNELED && m_size > 1) {
        std::fprintf(stderr, "error: this MPI library does not provide MPI_THREAD_FUNNELED\n");
        MPI_Abort(MPI_COMM_WORLD, 1);
    }
}

Session::~Session() {
    try {
        progress_sends(true);
    } catch (...) {
        // Finalizing regardless.
    }
    MPI_Finalize();
}

void Session::progress_sends(bool all) {
    for (auto it = m_sends.begin(); it != m_sends.end();) {
        int done = 0;
        if (all)
            check(MPI_Wait(&it->request, MPI_STATUS_IGNORE), "MPI_Wait");
        else
            check(MPI_Test(&it->request, &done, MPI_STATUS_IGNORE), "MPI_Test");
        if (all || done)
            it = m_sends.erase(it);
        else
            ++it;
    }
}

void Session::send(int to, const std::vector<char>& data) {
    if (data.size() > size_t(INT_MAX)) throw Error("MPI: a message of more than 2 GiB");
    progress_sends(false);
    Pending& p = m_sends.emplace_back();
    p.data = data;
    check(MPI_Isend(p.data.data(), int(p.data.size()), MPI_BYTE, to, kTag, MPI_COMM_WORLD,
                    &p.request),
          "MPI_Isend");
}

bool Session::try_receive(std::vector<char>& data, int& from) {
    progress_sends(false);
    int flag = 0;
    MPI_Status st;
    check(MPI_Iprobe(MPI_ANY_SOURCE, kTag, MPI_COMM_WORLD, &flag, &st), "MPI_Iprobe");
    if (!flag) return false;
    int count = 0;
    check(MPI_Get_count(&st, MPI_BYTE, &count), "MPI_Get_count");
    data.resize(size_t(count));
    from = st.MPI_SOURCE;
    check(MPI_Recv(data.data(), count, MPI_BYTE, from, kTag, MPI_COMM_WORLD, MPI_STATUS_IGNORE),
          "MPI_Recv");
    return true;
}

int Session::count_failed(bool failed) {
    int mine = failed ? 1 : 0, all = 0;
    check(MPI_Allreduce(&mine, &all, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD), "MPI_Allreduce");
    return all;
}

std::string Session::broadcast(const std::string& s) {
    unsigned long long n = s.size();
    check(MPI_Bcast(&n, 1, MPI_UNSIGNED_LONG_LONG, 0, MPI_COMM_WORLD), "MPI_Bcast");
    if (n > (unsigned long long)INT_MAX) throw Error("MPI: a broadcast of more than 2 GiB");
    std::string out = m_rank == 0 ? s : std::string(size_t(n), '\0');
    check(MPI_Bcast(out.data(), int(n), MPI_CHAR, 0, MPI_COMM_WORLD), "MPI_Bcast");
    return out;
}

double Session::sum_to_root(double v) {
    double total = 0;
    check(MPI_Reduce(&v, &total, 1, MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD), "MPI_Reduce");
    return total;
}

void Session::abort(int code) {
    MPI_Abort(MPI_COMM_WORLD, code);
    std::_Exit(code);
}

}  // namespace sr::mpi
