// Description: seconds per training epoch of a sigmoid MLP (default 16-48-2, the paper's Gregory network,
// on 83552 random patterns) for contactnn's full-batch, mini-batch and online modes, FANN's incremental
// training, and the machine's float matrix-product rate (a large Eigen GEMM), all at one thread count.
// scripts/bench-train runs it at 1 and 2 threads beside PyTorch and prints the comparison table.
//
// Sample runs:
//   build/bench/bench_train --threads 2
//   build/bench/bench_train --threads 1 --hidden 32 --only full --repeats 9
//
// Writes one line per measurement to stdout: `<method> threads=<T> sec_per_epoch=<best> samples=<s1,...>
// [extra=...]`, and `gemm threads=<T> gflops=<best> samples=<r1,...>`: every timed repetition (after an
// untimed warm-up) as seconds per epoch or GFLOP/s, so the caller can take minima and medians over several
// runs; a plain timing main, not a test.
#include <floatfann.h>
#include <omp.h>

#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "mlp/network.hpp"
#include "mlp/random.hpp"
#include "mlp/trainer.hpp"

namespace {

using namespace contactnn::mlp;
using Clock = std::chrono::steady_clock;

struct Args {
  int threads = 1;
  int inputs = 16;
  int hidden = 48;
  int outputs = 2;
  long patterns = 83552;
  std::size_t mini_batch = 1024;
  double u0 = 2.0;
  int repeats = 5;   // timed repetitions per method
  std::string only;  // run one method only: gemm, full, mini, online, fann
};

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Seconds of each of `repeats` runs of `body`: on a shared machine the least disturbed run is the minimum,
// and the median says how disturbed the others were.
template <class F>
std::vector<double> timings(int repeats, F&& body) {
  std::vector<double> seconds;
  for (int r = 0; r < repeats; ++r) {
    const auto start = Clock::now();
    body();
    seconds.push_back(seconds_since(start));
  }
  return seconds;
}

// `<name> threads=<T> sec_per_epoch=<best> samples=<s1,...>` for timings of `epochs` epochs each; no newline.
void print_epochs(const char* name, int threads, const std::vector<double>& seconds, int epochs) {
  std::printf("%s threads=%d sec_per_epoch=%.6g samples=", name, threads,
              *std::min_element(seconds.begin(), seconds.end()) / epochs);
  for (std::size_t i = 0; i < seconds.size(); ++i) std::printf("%s%.6g", i ? "," : "", seconds[i] / epochs);
}

void bench_gemm(const Args& a) {
  const int n = 2048;
  Eigen::setNbThreads(a.threads);
  Eigen::MatrixXf x = Eigen::MatrixXf::Random(n, n), y = Eigen::MatrixXf::Random(n, n), z(n, n);
  z.noalias() = x * y;  // warm-up: page faults and thread start-up
  const std::vector<double> seconds = timings(a.repeats, [&] { z.noalias() = x * y; });
  const double flops = 2.0 * n * n * double(n);
  std::printf("gemm threads=%d gflops=%.1f samples=", a.threads,
              flops / *std::min_element(seconds.begin(), seconds.end()) * 1e-9);
  for (std::size_t i = 0; i < seconds.size(); ++i)
    std::printf("%s%.1f", i ? "," : "", flops / seconds[i] * 1e-9);
  std::printf("\n");
}

void bench_contactnn(const Args& a, TrainingMode mode, std::size_t batch, const char* name, int epochs,
                     const MatrixRM<float>& x, const MatrixRM<float>& t) {
  Scaling s;
  s.input_min.assign(a.inputs, -1.0);
  s.input_max.assign(a.inputs, 1.0);
  s.output_min.assign(a.outputs, 0.1);
  s.output_max.assign(a.outputs, 0.9);
  Network<float> net({a.inputs, a.hidden, a.outputs}, a.u0, s);
  net.initialize(1);
  TrainOptions o;
  o.mode = mode;
  o.batch_size = batch;
  o.learning_rate = 0.01;
  o.momentum = 0.9;
  o.epochs = 1 << 30;
  o.threads = a.threads;
  const MatrixRM<float> none(0, a.inputs), none_t(0, a.outputs);
  Trainer<float> trainer(net, o, x, t, none, none_t);
  trainer.train_epoch();  // warm-up
  const std::vector<double> seconds = timings(a.repeats, [&] {
    for (int e = 0; e < epochs; ++e) trainer.train_epoch();
  });
  print_epochs(name, a.threads, seconds, epochs);
  std::printf(" loss=%.4g\n", trainer.state().training_loss);
}

void bench_fann(const Args& a, const MatrixRM<float>& x, const MatrixRM<float>& t) {
  const unsigned layers[3] = {static_cast<unsigned>(a.inputs), static_cast<unsigned>(a.hidden),
                              static_cast<unsigned>(a.outputs)};
  struct fann* ann = fann_create_standard_array(3, layers);
  fann_set_activation_function_hidden(ann, FANN_SIGMOID);
  fann_set_activation_function_output(ann, FANN_SIGMOID);
  // FANN's sigmoid is 1 / (1 + exp(-2 s x)): steepness s = 1/U0 is Eq 12.
  fann_set_activation_steepness_hidden(ann, static_cast<fann_type>(1.0 / a.u0));
  fann_set_activation_steepness_output(ann, static_cast<fann_type>(1.0 / a.u0));
  fann_set_training_algorithm(ann, FANN_TRAIN_INCREMENTAL);
  fann_set_learning_rate(ann, 0.01f);
  fann_set_learning_momentum(ann, 0.9f);
  fann_randomize_weights(ann, -0.1f, 0.1f);
  struct fann_train_data* data = fann_create_train(
      static_cast<unsigned>(x.rows()), static_cast<unsigned>(a.inputs), static_cast<unsigned>(a.outputs));
  for (Eigen::Index r = 0; r < x.rows(); ++r) {
    for (int i = 0; i < a.inputs; ++i) data->input[r][i] = x(r, i);
    for (int k = 0; k < a.outputs; ++k) data->output[r][k] = t(r, k);
  }
  float mse = fann_train_epoch(ann, data);  // warm-up
  const int epochs = 2;
  const std::vector<double> seconds = timings(a.repeats, [&] {
    for (int e = 0; e < epochs; ++e) mse = fann_train_epoch(ann, data);
  });
  print_epochs("fann-incremental", a.threads, seconds, epochs);
  std::printf(" mse=%.4g\n", mse);
  fann_destroy_train(data);
  fann_destroy(ann);
}

Args parse(int argc, char** argv) {
  Args a;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i], v = argv[i + 1];
    if (k == "--threads")
      a.threads = std::atoi(v.c_str());
    else if (k == "--hidden")
      a.hidden = std::atoi(v.c_str());
    else if (k == "--inputs")
      a.inputs = std::atoi(v.c_str());
    else if (k == "--patterns")
      a.patterns = std::atol(v.c_str());
    else if (k == "--mini-batch")
      a.mini_batch = static_cast<std::size_t>(std::atol(v.c_str()));
    else if (k == "--repeats")
      a.repeats = std::atoi(v.c_str());
    else if (k == "--only")
      a.only = v;
    else {
      std::fprintf(stderr, "bench_train: unknown option %s\n", k.c_str());
      std::exit(2);
    }
  }
  if (a.threads < 1 || a.repeats < 1 || a.patterns < 1 || a.inputs < 1 || a.hidden < 1) {
    std::fprintf(stderr,
                 "bench_train: --threads, --repeats, --patterns, --inputs and --hidden must be >= 1\n");
    std::exit(2);
  }
  return a;
}

}  // namespace

int main(int argc, char** argv) {
  const Args a = parse(argc, argv);
  omp_set_num_threads(a.threads);
  // Random inputs in [-1, 1], targets in [0.1, 0.9]: the timing does not depend on the values.
  Rng rng(42);
  MatrixRM<float> x(a.patterns, a.inputs), t(a.patterns, a.outputs);
  for (Eigen::Index r = 0; r < x.rows(); ++r) {
    for (int i = 0; i < a.inputs; ++i) x(r, i) = static_cast<float>(rng.uniform(-1, 1));
    for (int k = 0; k < a.outputs; ++k) t(r, k) = static_cast<float>(rng.uniform(0.1, 0.9));
  }
  auto want = [&](const char* m) { return a.only.empty() || a.only == m; };
  if (want("gemm")) bench_gemm(a);
  if (want("full")) bench_contactnn(a, TrainingMode::kBatch, 0, "contactnn-full-batch", 40, x, t);
  if (want("mini")) bench_contactnn(a, TrainingMode::kBatch, a.mini_batch, "contactnn-mini-batch", 10, x, t);
  if (want("online")) bench_contactnn(a, TrainingMode::kOnline, 0, "contactnn-online", 4, x, t);
  if (want("fann")) bench_fann(a, x, t);
  return 0;
}
