// `pcsim expand MODEL.toml|CASE.toml` (issue 22): prints the energy-form model file that pcsim
// derives from a model written with bodies, joints and forces (docs/bodies.md): the generated
// coordinates, definitions, T, V, F, generalized forces, named constraint rows and outputs.
// Running the printed file gives the same results, bit for bit (the same expressions reach the
// same derivation). An energy-form model prints as itself, normalized. Writes nothing else.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

#include <toml++/toml.h>

#include "cli/commands.hpp"
#include "common/error.hpp"
#include "modelfile/bodies.hpp"
#include "modelfile/model_source.hpp"

namespace {

namespace fs = std::filesystem;
using pcsim::InputError;

pcsim::modelfile::detail::ModelSource source_of(const fs::path& file) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec))
    throw InputError(file.string() + ": cannot read the file (no such file)");
  std::ifstream in(file, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  toml::table doc;
  try {
    doc = toml::parse(text.str(), file.string());
  } catch (const toml::parse_error& err) {
    std::ostringstream os;
    os << file.string();
    if (err.source().begin.line > 0) os << ":" << err.source().begin.line;
    os << ": not a valid TOML file: " << err.description();
    throw InputError(os.str());
  }
  const toml::node* m = doc.get("model");
  if (m && m->is_table()) {
    // A model file (only [model]) or a case with an inline [model] table.
    bool model_file = true;
    for (auto&& [k, v] : doc)
      if (k.str() != "model") model_file = false;
    if (model_file) return pcsim::modelfile::detail::parse_model_source_text(text.str(), file);
    return pcsim::modelfile::detail::read_model_source(*m->as_table(), file, "model");
  }
  if (m && m->is_string()) {
    fs::path p(*m->value<std::string>());
    if (p.extension() != ".toml")
      throw InputError(file.string() + ": key 'model': a model file path ending in .toml (pcsim "
                       "expand prints model files; '" + p.string() + "' is a built-in model)");
    if (p.is_relative()) p = file.parent_path() / p;
    return pcsim::modelfile::detail::load_model_source(p);
  }
  throw InputError(file.string() + ": key 'model': a [model] table (a model file) or a case "
                   "whose model is a model file");
}

void setup(CLI::App& app) {
  auto file = std::make_shared<std::string>();
  CLI::App* sub = app.add_subcommand(
      "expand", "Print the energy-form model file (T, V, F, forces, named constraints, outputs) "
                "that pcsim derives from a model with bodies and joints; running it gives the "
                "same results");
  sub->add_option("model", *file, "a model file or a case file naming one")->required();
  sub->callback([file]() {
    const auto src = source_of(*file);
    const std::string text = pcsim::modelfile::bodies::energy_form_text(src);
    std::fwrite(text.data(), 1, text.size(), stdout);
  });
}

const bool registered = pcsim::cli::register_command(13, &setup);

}  // namespace
