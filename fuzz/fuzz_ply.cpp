// libFuzzer harness: the PLY reader (src/io/read_ply.cpp) on arbitrary bytes. Every input must end
// in PlyData or a Status; a crash, hang, sanitizer report or oversized allocation is a finding.
#include "fuzz_support.h"

#include "io/read_ply.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    static bool ready = (standin::fuzz::lower_budgets(), true);
    (void)ready;
    std::string path = standin::fuzz::write_input("input.ply", data, size);
    standin::Result<standin::PlyData> ply = standin::read_ply(path);
    if (ply) {
        // what import relies on: every index refers to a vertex
        for (std::uint32_t i : ply->triangles)
            if (i >= ply->positions.size()) __builtin_trap();
    }
    return 0;
}
