// `standin bake` over a library of models: several models, folders of them or list files, into one
// output folder, each package skipped when it is up to date (same model bytes, representation and
// requested options), one shard of N when a cluster scheduler runs it as a job array, and a JSON
// summary of what happened to each model (docs/FORMAT.md, "Batch summary").
#pragma once

#include <standin/options.h>
#include <standin/package.h>
#include <standin/status.h>

#include <string>
#include <vector>

namespace standin::cli {

struct BatchArgs {
    std::vector<std::string> inputs; // model files and folders of them
    std::string list;                // a file naming one model per line (relative to it), or empty
    std::string output;              // the output folder
    const Representation* representation = nullptr;
    OptionValues parameters;
    int threads = 0;
    int shard = 0, shards = 1;       // this process bakes the models k with k % shards == shard
    bool force = false;              // bake even what is up to date
    bool evaluate = true;            // measure the error at distance 1 (quick protocol)
};

// Whether a bake command line asks for batch mode: several inputs, a folder, a list, or an output
// that is not NAME.standin.
bool is_batch(const std::vector<std::string>& inputs, const std::string& list, const std::string& output);

// "I/N", or SLURM_ARRAY_TASK_ID (minus SLURM_ARRAY_TASK_MIN) and SLURM_ARRAY_TASK_COUNT when
// `text` is empty and they are set; 0/1 otherwise.
Status parse_shard(const std::string& text, int& shard, int& shards);

// Bakes the shard's models. Returns the exit status: 0 when every model was baked or up to date, 2
// when one failed (each failure is a line on stderr and an entry in the summary) or when the batch
// itself cannot run (no models, an output folder that cannot be made).
int run_batch(const BatchArgs& args);

} // namespace standin::cli
