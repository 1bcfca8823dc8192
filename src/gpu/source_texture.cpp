// Source textures on the GPU with the truth's mip levels (source_texture.h; why coverage-weighted:
// src/reference/mesh_renderer.cpp).
#include "gpu/source_texture.h"

#include <algorithm>
#include <cmath>
#include <functional>

namespace standin::gpu {

namespace {

bool has_alpha(const standin::Texture& texture)
{
    for (std::size_t i = 3; i < texture.rgba.size(); i += 4)
        if (texture.rgba[i] != 255) return true;
    return false;
}

standin::Texture resampled(const standin::Texture& texture, int width, int height)
{
    standin::Texture out;
    out.name = texture.name;
    out.width = width;
    out.height = height;
    out.rgba.resize(std::size_t(width) * height * 4);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            glm::vec4 c = texture.sample({(float(x) + 0.5f) / float(width), (float(y) + 0.5f) / float(height)});
            for (int k = 0; k < 4; ++k)
                out.rgba[(std::size_t(y) * width + x) * 4 + std::size_t(k)] = std::uint8_t(std::lround(std::clamp(c[k], 0.0f, 1.0f) * 255.0f));
        }
    return out;
}

// `texture` repeated kx x ky times: what reads the copy at uv / k (repeating) sees the texture at
// uv, texel for texel, and at every mip level down to where the texture's size turns odd.
standin::Texture tiled(const standin::Texture& texture, int kx, int ky)
{
    standin::Texture out;
    out.name = texture.name;
    out.width = texture.width * kx;
    out.height = texture.height * ky;
    out.rgba.resize(std::size_t(out.width) * std::size_t(out.height) * 4);
    const std::size_t row = std::size_t(texture.width) * 4;
    for (int y = 0; y < out.height; ++y)
        for (int x = 0; x < kx; ++x)
            std::copy_n(&texture.rgba[std::size_t(y % texture.height) * row], row,
                        &out.rgba[(std::size_t(y) * std::size_t(out.width) + std::size_t(x) * std::size_t(texture.width)) * 4]);
    return out;
}

int level_count(int width, int height) { return 1 + int(std::floor(std::log2(std::max(width, height)))); }

void set_sampling(GLuint handle)
{
    glTextureParameteri(handle, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTextureParameteri(handle, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(handle, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTextureParameteri(handle, GL_TEXTURE_WRAP_T, GL_REPEAT);
}

// The next coverage-weighted mip level of an RGBA8 image (w x h): each texel the 2 x 2 (1 x 2 or
// 2 x 1 along a side of size 1) block under it; colour weighted by alpha, alpha the plain mean. A
// block with no coverage takes its covered neighbours' colour.
std::vector<std::uint8_t> coverage_weighted_level(const std::vector<std::uint8_t>& fine, int w, int h)
{
    const int nw = std::max(1, w / 2), nh = std::max(1, h / 2);
    std::vector<std::uint8_t> out(std::size_t(nw) * nh * 4);
    for (int y = 0; y < nh; ++y)
        for (int x = 0; x < nw; ++x) {
            double weighted[3] = {0, 0, 0}, plain[3] = {0, 0, 0}, alpha = 0.0;
            int count = 0;
            for (int dy = 0; dy < (h > 1 ? 2 : 1); ++dy)
                for (int dx = 0; dx < (w > 1 ? 2 : 1); ++dx) {
                    const std::uint8_t* t = &fine[(std::size_t(2 * y + dy) * w + std::size_t(2 * x + dx)) * 4];
                    for (int c = 0; c < 3; ++c) weighted[c] += double(t[c]) * t[3], plain[c] += t[c];
                    alpha += t[3];
                    ++count;
                }
            std::uint8_t* o = &out[(std::size_t(y) * nw + std::size_t(x)) * 4];
            for (int c = 0; c < 3; ++c)
                o[c] = std::uint8_t(std::lround(alpha > 0.0 ? weighted[c] / alpha : plain[c] / count));
            o[3] = std::uint8_t(std::lround(alpha / count));
        }
    // an empty texel takes the mean colour of its covered neighbours (wrapping, as the sampler
    // does), so that bilinear lookups at a cut-out's rim do not mix in the empty texels' colour
    std::vector<std::uint8_t> filled = out;
    for (int y = 0; y < nh; ++y)
        for (int x = 0; x < nw; ++x) {
            std::uint8_t* o = &filled[(std::size_t(y) * nw + std::size_t(x)) * 4];
            if (o[3] != 0) continue;
            int sum[3] = {0, 0, 0}, n = 0;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    int nx = (x + dx + nw) % nw, ny = (y + dy + nh) % nh;
                    const std::uint8_t* t = &out[(std::size_t(ny) * nw + std::size_t(nx)) * 4];
                    if (t[3] == 0) continue;
                    for (int c = 0; c < 3; ++c) sum[c] += t[c];
                    ++n;
                }
            if (n > 0)
                for (int c = 0; c < 3; ++c) o[c] = std::uint8_t((sum[c] + n / 2) / n);
        }
    return filled;
}

// Levels 1.. of `rgba` (w x h), coverage-weighted, each handed to `store` (level, width, height, texels).
void for_each_coverage_level(const std::vector<std::uint8_t>& rgba, int w, int h, int levels,
                             const std::function<void(int, int, int, const std::uint8_t*)>& store)
{
    std::vector<std::uint8_t> level = rgba;
    for (int l = 1; l < levels; ++l) {
        level = coverage_weighted_level(level, w, h);
        w = std::max(1, w / 2), h = std::max(1, h / 2);
        store(l, w, h, level.data());
    }
}

} // namespace

Texture upload_source_texture(const standin::Texture& texture)
{
    const int levels = level_count(texture.width, texture.height);
    Texture handle = make_texture_2d(GL_RGBA8, texture.width, texture.height, levels);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage2D(handle.get(), 0, 0, 0, texture.width, texture.height, GL_RGBA, GL_UNSIGNED_BYTE,
                        texture.rgba.data());
    if (has_alpha(texture)) {
        for_each_coverage_level(texture.rgba, texture.width, texture.height, levels, [&](int l, int w, int h, const std::uint8_t* texels) {
            glTextureSubImage2D(handle.get(), l, 0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, texels);
        });
    } else {
        glGenerateTextureMipmap(handle.get());
    }
    set_sampling(handle.get());
    return handle;
}

namespace {

Texture upload_array(const std::vector<const standin::Texture*>& sources, std::vector<glm::vec2>* uv_scale)
{
    int width = 0, height = 0;
    for (const standin::Texture* t : sources) width = std::max(width, t->width), height = std::max(height, t->height);
    // (only layers of another size are copied: tiled where they divide the array's size, else
    // resampled)
    std::vector<standin::Texture> resized(sources.size());
    std::vector<const standin::Texture*> layers;
    if (uv_scale) uv_scale->assign(sources.size(), glm::vec2(1.0f));
    for (std::size_t k = 0; k < sources.size(); ++k) {
        const standin::Texture& t = *sources[k];
        const bool same = t.width == width && t.height == height;
        if (!same && uv_scale && width % t.width == 0 && height % t.height == 0) {
            resized[k] = tiled(t, width / t.width, height / t.height);
            (*uv_scale)[k] = glm::vec2(float(t.width) / float(width), float(t.height) / float(height));
        } else if (!same) {
            resized[k] = resampled(t, width, height);
        }
        layers.push_back(same ? sources[k] : &resized[k]);
    }
    const int levels = level_count(width, height);
    GLuint name = 0;
    glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &name);
    Texture handle(name);
    glTextureStorage3D(name, levels, GL_RGBA8, width, height, GLsizei(layers.size()));
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    for (std::size_t k = 0; k < layers.size(); ++k)
        glTextureSubImage3D(name, 0, 0, 0, GLint(k), width, height, 1, GL_RGBA, GL_UNSIGNED_BYTE, layers[k]->rgba.data());
    glGenerateTextureMipmap(name);
    for (std::size_t k = 0; k < layers.size(); ++k)
        if (has_alpha(*layers[k]))
            for_each_coverage_level(layers[k]->rgba, width, height, levels, [&](int l, int w, int h, const std::uint8_t* texels) {
                glTextureSubImage3D(name, l, 0, 0, GLint(k), w, h, 1, GL_RGBA, GL_UNSIGNED_BYTE, texels);
            });
    set_sampling(name);
    return handle;
}

} // namespace

Texture upload_source_texture_array(const std::vector<standin::Texture>& sources, std::vector<glm::vec2>* uv_scale)
{
    std::vector<const standin::Texture*> pointers;
    for (const standin::Texture& t : sources) pointers.push_back(&t);
    return upload_array(pointers, uv_scale);
}

std::vector<std::uint32_t> source_texture_array_of(const std::vector<standin::Texture>& textures, int max_arrays)
{
    std::vector<std::size_t> order(textures.size());
    for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
    auto area = [&](std::size_t k) { return std::uint64_t(textures[k].width) * std::uint64_t(textures[k].height); };
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
        if (area(a) != area(b)) return area(a) > area(b);
        return textures[a].width > textures[b].width;
    });
    std::vector<glm::ivec2> array_size; // each array's first (largest) size
    std::vector<std::uint32_t> array_of(textures.size(), 0u);
    for (std::size_t k : order) {
        const glm::ivec2 size(std::max(1, textures[k].width), std::max(1, textures[k].height));
        std::size_t a = 0;
        while (a < array_size.size() && (array_size[a].x % size.x != 0 || array_size[a].y % size.y != 0)) ++a;
        if (a == array_size.size()) {
            if (int(array_size.size()) < std::max(1, max_arrays)) array_size.push_back(size);
            else a = 0;
        }
        array_of[k] = std::uint32_t(a);
    }
    return array_of;
}

SourceTextureArrays upload_source_texture_arrays(const std::vector<standin::Texture>& textures, int max_arrays)
{
    SourceTextureArrays out;
    out.array_of = source_texture_array_of(textures, max_arrays);
    out.layer_of.assign(textures.size(), 0u);
    out.uv_scale.assign(textures.size(), glm::vec2(1.0f));
    const std::uint32_t arrays = textures.empty() ? 0u : *std::max_element(out.array_of.begin(), out.array_of.end()) + 1u;
    for (std::uint32_t a = 0; a < arrays; ++a) {
        std::vector<const standin::Texture*> members;
        std::vector<std::size_t> index;
        for (std::size_t k = 0; k < textures.size(); ++k)
            if (out.array_of[k] == a) out.layer_of[k] = std::uint32_t(members.size()), members.push_back(&textures[k]), index.push_back(k);
        std::vector<glm::vec2> scale;
        out.arrays.push_back(upload_array(members, &scale));
        for (std::size_t m = 0; m < index.size(); ++m) out.uv_scale[index[m]] = scale[m];
    }
    return out;
}

} // namespace standin::gpu
