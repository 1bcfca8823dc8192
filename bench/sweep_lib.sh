# Shared by the sweeps over Debian's assimp-testmodels (bench/change_sweep.sh, bench/quality_sweep.sh):
# which files are models, and the two figures read from `standin eval`'s report.

# Model files under $1 of at most $2 MB (default 3), sorted: images, material and text side files,
# and the folders of reference pictures, source files, deliberately broken and parser-only files left out.
sweep_models() {
  local skip='\.(png|jpg|jpeg|bmp|tga|dds|txt|mtl|bin|pcx|gif|tif|md|xml|skin|shader|material|ktx|webp)$'
  find "$1" -type f -size -"${2:-3}"M | grep -Eiv "$skip" |
    grep -vE '/(ReferenceImages|SourceFiles|invalid|ParsingFiles)/' | sort
}

# A file name for a model: its path under the models folder with '/', ' ', '(' and ')' as '_'.
sweep_name() { echo "${1#"$2"/}" | tr '/ ()' '____'; }

# "LUV IOU" from an eval report (text, not JSON).
eval_summary() {
  sed -n 's/^ *Luv (eq. 2.2) *mean \([0-9.]*\).*/\1/p; s/^ *coverage .*IoU \([0-9.]*\).*/\1/p' "$1" | tr '\n' ' '
}
