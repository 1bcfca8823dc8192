// libFuzzer harness: the KTX2 reader of compressed package images (src/reps/common/package_codec.cpp,
// decode_ktx2: the enhanced billboards' maps and the view atlas's compressed pages) on arbitrary
// bytes, with the format, size and level count a manifest would give taken from the file's own
// header (sizes capped at 1024 so that inputs stay cheap) so that inputs reach the level index and
// zlib. Every input must end in levels of exactly the bytes their format needs, which the block
// decoder then reads, or a one-line Status; a crash, hang, sanitizer report or oversized allocation
// is a finding.
#include "fuzz_support.h"

#include "reps/common/block_compress.h"
#include "reps/common/package_codec.h"

#include <squish.h>

#include <algorithm>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    using standin::manifest_io::BlockFormat;
    static bool ready = (standin::fuzz::lower_budgets(), true);
    (void)ready;
    std::string_view bytes(reinterpret_cast<const char*>(data), size);
    auto header = [&](std::size_t at) { return standin::fuzz::input_u32(data, size, at); };
    const BlockFormat formats[] = {BlockFormat::bc3_srgb, BlockFormat::bc4, BlockFormat::bc5, BlockFormat::r16, BlockFormat::r8};
    BlockFormat format = formats[header(12) % 5];
    for (BlockFormat f : formats)
        if (std::uint32_t(f) == header(12)) format = f;
    const int width = int(std::clamp<std::uint32_t>(header(20), 1, 1024));
    const int height = int(std::clamp<std::uint32_t>(header(24), 1, 1024));
    const int levels = int(std::clamp<std::uint32_t>(header(40), 1, 11));
    standin::Result<standin::manifest_io::BlockImage> image =
        standin::manifest_io::decode_ktx2(bytes, "input.ktx2", format, width, height, levels);
    if (!image) {
        if (image.status().message().find('\n') != std::string::npos) __builtin_trap(); // one line
        return 0;
    }
    if (image->levels.size() != std::size_t(levels)) __builtin_trap();
    for (int m = 0; m < levels; ++m)
        if (image->levels[std::size_t(m)].size() !=
            standin::manifest_io::level_bytes(format, std::max(width >> m, 1), std::max(height >> m, 1)))
            __builtin_trap();
    const int flags = format == BlockFormat::bc3_srgb ? squish::kDxt5
                      : format == BlockFormat::bc4    ? squish::kBc4
                      : format == BlockFormat::bc5    ? squish::kBc5
                                                      : 0;
    if (flags) (void)standin::reps::decompress_blocks(image->levels[0].data(), width, height, flags);
    return 0;
}
