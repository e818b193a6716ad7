// The MPI tests' main: MPI around GoogleTest. Rank 0 prints the usual report; the other ranks
// print only their failures, tagged with their rank. The exit status is the worst rank's.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cstdio>

namespace {

class failures_only : public ::testing::EmptyTestEventListener {
public:
    explicit failures_only(int rank) : rank_(rank) {}
    void OnTestPartResult(const ::testing::TestPartResult& result) override {
        if (result.failed())
            std::printf("[rank %d] %s:%d: failure\n%s\n", rank_, result.file_name() ? result.file_name() : "?",
                        result.line_number(), result.summary());
    }

private:
    int rank_;
};

}  // namespace

int main(int argc, char** argv) {
    MPI_Init(&argc, &argv);
    ::testing::InitGoogleTest(&argc, argv);
    int rank = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    if (rank != 0) {
        auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
        delete listeners.Release(listeners.default_result_printer());
        listeners.Append(new failures_only(rank));
    }
    int failed = RUN_ALL_TESTS();
    MPI_Allreduce(MPI_IN_PLACE, &failed, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    if (rank == 0 && failed) std::printf("some rank failed: see the [rank k] lines above\n");
    MPI_Finalize();
    return failed;
}
