// libFuzzer harness: the compact coarse-mesh decoder (src/reps/common/coarse_mesh.cpp,
// decode_coarse_mesh) on arbitrary bytes, with the counts the manifest would give taken from the
// file's own header so that inputs reach the codecs. Every input must end in a Mesh whose indices
// are in range or a Status; a crash, hang, sanitizer report or oversized allocation is a finding.
#include "fuzz_support.h"

#include "reps/common/coarse_mesh.h"

#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    static bool ready = (standin::fuzz::lower_budgets(), true);
    (void)ready;
    std::string_view bytes(reinterpret_cast<const char*>(data), size);
    auto header = [&](std::size_t at) { return standin::fuzz::input_u32(data, size, at); };
    standin::Result<standin::Mesh> mesh = standin::reps::decode_coarse_mesh(bytes, "input.meshopt", header(16), header(12));
    if (mesh) {
        for (std::uint32_t i : mesh->indices)
            if (i >= mesh->vertex_count()) __builtin_trap();
        if (mesh->normals.size() != mesh->vertex_count()) __builtin_trap();
    }
    return 0;
}
