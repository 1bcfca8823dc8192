// libFuzzer harness: the whole mesh import path (import_mesh: our PLY reader or assimp, the scene
// conversion, normals, validation). The first byte picks the file extension, so one corpus reaches
// every format; run with -timeout and -rss_limit_mb (scripts/fuzz does) for the per-input limits.
#include "fuzz_support.h"

#include <standin/mesh.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    static bool ready = (standin::fuzz::lower_budgets(), true);
    (void)ready;
    static const char* const k_extensions[] = {"ply", "obj", "off", "stl", "gltf", "glb", "dae", "3ds", "fbx", "x"};
    if (size < 1) return 0;
    const char* extension = k_extensions[data[0] % (sizeof k_extensions / sizeof *k_extensions)];
    std::string path = standin::fuzz::write_input(std::string("input.") + extension, data + 1, size - 1);
    standin::Result<standin::Mesh> mesh = standin::import_mesh(path);
    if (mesh && !standin::validate_mesh(*mesh, path).is_ok()) __builtin_trap(); // import's promise
    return 0;
}
