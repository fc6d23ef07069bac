// `raybench bench`: kernel benchmarks: scalar against 8 and 16 SIMD lanes.
#include "apps/cli/command.hpp"
#include "apps/report/report.hpp"

namespace rb::app::cli {
namespace {

class BenchCommand final : public Command {
  BenchOptions bo;
  bool bench_list = false;
 public:
  explicit BenchCommand(CLI::App& root) : Command(root, "bench", "Kernel benchmarks: scalar against 8 and 16 lanes") {
    sub_->add_option("--filter", bo.filter, "Only the benchmarks whose name\n(kernel/method/variant/case) matches this regex")
        ->capture_default_str();
    sub_->add_option("-r,--repetitions", bo.repetitions, "Rounds: each runs every selected benchmark\nonce; a benchmark's repetitions are its rounds\n(the median is quoted; from 6, ratios carry a\n95 % interval; from 9 it leaves out the most\nextreme round on each side)")->capture_default_str()->check(CLI::Range(1, 100));
    sub_->add_option("--min-time", bo.min_time, "Seconds per benchmark per round")->capture_default_str()->check(CLI::Range(0.001, 10.0));
    sub_->add_option("--extra-rounds", bo.extra_rounds,
                     "Then up to N more rounds, each of every form of\nthe cases one of whose ratios (SIMD / scalar,\n16 / 8 lanes) "
                     "has an interval wider than\n--within, and of the lone benchmarks whose\nrate's interval is (the node test)")
        ->capture_default_str()->check(CLI::Range(0, 100));
    sub_->add_option_function<double>("--within", [this](double p) { bo.within = p / 100; }, "Half-width in % an interval is held to (the\nrule for --extra-rounds) [5]")
        ->check(CLI::Range(0.001, 100.0));
    sub_->add_option("--isa", bo.isa, "auto: 16 AVX-512 lanes beside 8 AVX2 lanes where\nthe CPU and the build have them; avx2: 8 lanes\nonly; avx512: fail where 16 lanes cannot run")
        ->capture_default_str()->check(CLI::IsMember({"auto", "avx2", "avx512"}));
    sub_->add_option("--seed", bo.seed, "Seed of the rays and primitives\n(0: the report's data)")->capture_default_str();
    sub_->add_flag("--list", bench_list, "List the benchmarks the filter selects and exit");
    json_option("Google Benchmark JSON, every repetition, to FILE\n(no FILE: stdout instead of the table)");
    history_option();
    sub_->footer(
        "Google Benchmark medians, L1-resident, one thread: every kernel x {true scalar,\n"
        "8 rays x 1 primitive, 1 ray x 8 primitives (AVX2), and with AVX-512 16 rays x 1\n"
        "primitive, 1 ray x 16 primitives} x {hit, miss, half}, run in rounds\n"
        "(each round every benchmark once, a method's scalar, 8-lane and 16-lane forms\n"
        "of one case back to back). The table shows the median tests per second, the\n"
        "coefficient of variation over the rounds, operations per test and the SIMD\n"
        "speedup over the scalar form (the median of the rounds' ratios; --json gives\n"
        "its 95 % interval under raybench_simd_vs_scalar; 16 over 8 lanes under\n"
        "raybench_simd16_vs_simd8, per method below the table with the reason where\n"
        "it falls short of 1.6x; the ISA under raybench_isa). The --json file is what\n"
        "Google Benchmark's compare.py and `raybench compare` read.");
  }
  int run(Context& c) override {
    if (!bench_list && !open_history(c)) return kExitError;
    const JsonOut out = recorded_json_out(c);
    return run_bench_command(bo, bench_list, out);
  }
};

}  // namespace

std::unique_ptr<Command> make_bench(CLI::App& root) { return std::make_unique<BenchCommand>(root); }

}  // namespace rb::app::cli
