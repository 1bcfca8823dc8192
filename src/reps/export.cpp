// Representation-independent export (export.h): options checked against the representation's
// declaration, its scene encoded as .glb, written under a temporary name and renamed into place.
#include <standin/export.h>
#include <standin/files.h>
#include <standin/package.h>

#include <utility>

namespace standin {

Status export_package(const Package& package, const OptionValues& given, const std::string& output, ExportScene* scene_out)
{
    const Representation& representation = representation_of(package);
    if (!representation.export_scene)
        return error(StatusCode::unsupported, representation.name + " packages cannot be exported yet");
    Result<Options> options = Options::parse(representation.export_options, given, representation.name + " packages");
    if (!options) return options.status();
    STANDIN_RETURN_IF_ERROR(check_output_path(output));
    Result<ExportScene> scene = representation.export_scene(package, *options);
    if (!scene) return scene.status();
    scene->extras["standin"]["representation"] = representation.name;
    scene->extras["standin"]["source"] = {{"file", package.source.file_name},
                                          {"content_hash", package.source.content_hash},
                                          {"triangles", package.source.triangles}};
    scene->extras["standin"]["format_version"] = k_export_format_version;
    scene->gpu_bytes = 0;
    for (const ExportTexture& t : scene->textures) scene->gpu_bytes += export_texture_bytes(t);
    for (const ExportMesh& m : scene->meshes) scene->gpu_bytes += export_mesh_bytes(m);
    Result<std::string> glb = encode_glb(*scene, "standin 0.1.0");
    if (!glb) return naming_file(glb.status(), output);
    STANDIN_RETURN_IF_ERROR(write_file_atomic(output, *glb));
    if (scene_out) *scene_out = std::move(*scene);
    return Status::ok();
}

} // namespace standin
