#include "modelfile/tape_io.hpp"

#include <cstring>
#include <stdexcept>
#include <type_traits>

#include "modelfile/expression_model.hpp"

namespace pcsim::modelfile {

namespace {

// 2: contact attributes (issue 12); 3: lambda slots (issue 22); 4: rough rows (issue 22)
constexpr char kTag[] = "pcsim-compiled-model-4";

class Writer {
 public:
  template <class T> void pod(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    out.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  void str(const std::string& s) {
    pod<std::uint64_t>(s.size());
    out += s;
  }
  template <class T> void pods(const std::vector<T>& v) {
    pod<std::uint64_t>(v.size());
    for (const auto& x : v) item(x);
  }
  // Structures field by field, so no padding byte reaches the output.
  template <class T> void item(const T& x) { pod(x); }
  void item(const Instr& x) {
    pod(static_cast<std::uint16_t>(x.op));
    pod(x.dst);
    pod(x.a);
    pod(x.b);
    pod(x.c);
  }
  void item(const std::pair<std::uint32_t, double>& x) {
    pod(x.first);
    pod(x.second);
  }
  std::string out;
};

class Reader {
 public:
  explicit Reader(const std::string& b) : b_(b) {}
  template <class T> T pod() {
    static_assert(std::is_trivially_copyable_v<T>);
    if (pos_ + sizeof(T) > b_.size()) throw std::runtime_error("truncated");
    T v;
    std::memcpy(&v, b_.data() + pos_, sizeof v);
    pos_ += sizeof v;
    return v;
  }
  std::string str() {
    const auto n = pod<std::uint64_t>();
    if (pos_ + n > b_.size()) throw std::runtime_error("truncated");
    std::string s = b_.substr(pos_, n);
    pos_ += n;
    return s;
  }
  template <class T> std::vector<T> pods() {
    const auto n = pod<std::uint64_t>();
    if (n > b_.size()) throw std::runtime_error("corrupt");
    std::vector<T> v;
    v.reserve(n);
    for (std::uint64_t i = 0; i < n; ++i) v.push_back(item(static_cast<T*>(nullptr)));
    return v;
  }
  template <class T> T item(T*) { return pod<T>(); }
  Instr item(Instr*) {
    Instr x;
    x.op = static_cast<Op>(pod<std::uint16_t>());
    x.dst = pod<std::uint32_t>();
    x.a = pod<std::uint32_t>();
    x.b = pod<std::uint32_t>();
    x.c = pod<std::uint32_t>();
    return x;
  }
  std::pair<std::uint32_t, double> item(std::pair<std::uint32_t, double>*) {
    const auto first = pod<std::uint32_t>();
    return {first, pod<double>()};
  }
  bool done() const { return pos_ == b_.size(); }

 private:
  const std::string& b_;
  std::size_t pos_ = 0;
};

}  // namespace

unsigned long long text_hash(const std::string& text) {
  unsigned long long h = 1469598103934665603ull;
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
}

std::string serialize_compiled(const CompiledModel& c, const std::string& text) {
  Writer w;
  w.str(kTag);
  w.pod<unsigned long long>(text_hash(text));
  w.str(c.name);
  w.pod<std::uint64_t>(c.coordinates.size());
  for (const auto& s : c.coordinates) w.str(s);
  w.pod<std::uint64_t>(c.constraints.size());
  for (const auto& k : c.constraints) {
    w.str(k.name);
    w.pod<int>(static_cast<int>(k.kind));
    w.pod<bool>(k.constant_row);
    w.pod<bool>(k.active_by_default);
    w.pod<bool>(k.contact.unilateral);  // contact attributes (issue 12); values: contact_slots
    w.pod<int>(k.contact.gap_sign);
    w.pod<int>(k.contact.friction_of);
    w.pod<bool>(k.contact.rough);
  }
  w.pod<std::uint64_t>(c.output_names.size());
  for (const auto& s : c.output_names) w.str(s);
  const Tape& t = c.tape;
  w.pod(t.n);
  w.pod(t.n_slots);
  w.pod(t.n_constant);
  w.pod(t.zero_slot);
  w.pods(t.literals);
  w.pods(t.parameter_slots);
  w.pods(t.hidden_slots);
  w.pod(t.t_slot);
  w.pod(t.q_slot);
  w.pod(t.qd_slot);
  w.pod(t.qdd_slot);
  w.pod(t.R_slot);
  w.pod(t.lambda_slot);
  w.pod(t.n_lambda);
  w.pods(t.prelude);
  w.pod<std::uint64_t>(t.blocks.size());
  for (const auto& b : t.blocks) {
    w.pods(b.code);
    w.pods(b.results);
  }
  w.pod(c.kinetic_block);
  w.pod(c.forces_block);
  w.pod(c.outputs_block);
  w.pod<std::uint64_t>(c.constraint_blocks.size());
  for (const auto& b : c.constraint_blocks) {
    w.pod(b.rows);
    w.pod(b.position);
    w.pod(b.hidden);
    for (std::int64_t slot : b.contact_slots) w.pod(slot);
  }
  w.pod(c.period_slot);
  return w.out;
}

std::shared_ptr<CompiledModel> deserialize_compiled(const std::string& bytes, const std::string& text) {
  try {
    Reader r(bytes);
    if (r.str() != kTag) return nullptr;
    if (r.pod<unsigned long long>() != text_hash(text)) return nullptr;
    auto c = std::make_shared<CompiledModel>();
    c->name = r.str();
    for (auto n = r.pod<std::uint64_t>(); n > 0; --n) c->coordinates.push_back(r.str());
    for (auto n = r.pod<std::uint64_t>(); n > 0; --n) {
      mech::ConstraintInfo k;
      k.name = r.str();
      k.kind = static_cast<mech::ConstraintKind>(r.pod<int>());
      k.constant_row = r.pod<bool>();
      k.active_by_default = r.pod<bool>();
      k.contact.unilateral = r.pod<bool>();
      k.contact.gap_sign = r.pod<int>();
      k.contact.friction_of = r.pod<int>();
      k.contact.rough = r.pod<bool>();
      c->constraints.push_back(k);
    }
    for (auto n = r.pod<std::uint64_t>(); n > 0; --n) c->output_names.push_back(r.str());
    Tape& t = c->tape;
    t.n = r.pod<int>();
    t.n_slots = r.pod<std::uint32_t>();
    t.n_constant = r.pod<std::uint32_t>();
    t.zero_slot = r.pod<std::uint32_t>();
    t.literals = r.pods<std::pair<std::uint32_t, double>>();
    t.parameter_slots = r.pods<std::uint32_t>();
    t.hidden_slots = r.pods<std::uint32_t>();
    t.t_slot = r.pod<std::uint32_t>();
    t.q_slot = r.pod<std::uint32_t>();
    t.qd_slot = r.pod<std::uint32_t>();
    t.qdd_slot = r.pod<std::uint32_t>();
    t.R_slot = r.pod<std::uint32_t>();
    t.lambda_slot = r.pod<std::uint32_t>();
    t.n_lambda = r.pod<std::uint32_t>();
    t.prelude = r.pods<Instr>();
    for (auto n = r.pod<std::uint64_t>(); n > 0; --n) {
      Block b;
      b.code = r.pods<Instr>();
      b.results = r.pods<std::uint32_t>();
      t.blocks.push_back(std::move(b));
    }
    c->kinetic_block = r.pod<int>();
    c->forces_block = r.pod<int>();
    c->outputs_block = r.pod<int>();
    for (auto n = r.pod<std::uint64_t>(); n > 0; --n) {
      CompiledModel::ConstraintBlocks b;
      b.rows = r.pod<int>();
      b.position = r.pod<int>();
      b.hidden = r.pod<int>();
      for (std::int64_t& slot : b.contact_slots) slot = r.pod<std::int64_t>();
      c->constraint_blocks.push_back(b);
    }
    c->period_slot = r.pod<std::int64_t>();
    if (!r.done()) return nullptr;
    c->index_entries();
    return c;
  } catch (const std::exception&) {
    return nullptr;
  }
}

}  // namespace pcsim::modelfile
