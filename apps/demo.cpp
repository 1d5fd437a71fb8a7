// demo: the framework end to end in a few seconds, on built-in synthetic data.
//
// A small conv net (conv 3x3 -> batchnorm -> relu -> conv 3x3) learns an edge detector,
// |sobel_x * x| + |sobel_y * x|, on random smooth images: relu(a) + relu(-a) = |a|, so
// the net can represent the target exactly and the loss falls towards 0. Then the
// weights are saved as a blob (docs/weights-format.md), loaded into a fresh model, and
// the reloaded model must give bitwise the same validation loss.
//
//   demo                               default: 2 threads, 20 epochs, ./demo-out
//   demo --threads 1 --epochs 30 --out /tmp/demo
#include <string>

#include "apps/args.h"
#include "core/folder_lock.h"
#include "core/thread_pool.h"
#include "runs/edge_demo.h"

using namespace nns;

int main(int argc, char** argv) {
  return apps::run_main("demo", [&] {
    apps::Args a(argc, argv, "demo",
                 "Train a small conv net on built-in synthetic data, save its weights, reload them.");
    int threads = a.get_int("--threads", 2, "worker threads", 1, 256);
    int seed = a.get_int("--seed", 1, "random seed (weights and data)", 0, INT_MAX);
    int epochs = a.get_int("--epochs", 20, "training epochs", 1, 100000);
    int width = a.get_int("--width", 8, "hidden channels", 1, 4096);
    std::string out = a.get_path("--out", "demo-out", "output folder for the weights blob");
    a.done();
    set_num_threads(threads);
    FolderLock lock = prepare_output_folder(out, "demo");
    return runs::run_edge_demo(threads, seed, epochs, width, out);
  });
}
