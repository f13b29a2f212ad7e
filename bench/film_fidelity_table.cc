// Prints the work-precision table of the film field fidelity levels: time per evaluation, the
// field's max relative error and the force error it causes, each against a fine reference
// (tiles:128). The force error is what the DUT would see: a (.) dS over the operating volume of the
// calibration loads, with S re-zeroed at the rest pose as the DUT's start-up no-load averaging
// does, using the gains a of a calibration run on the reference. Usage: hilrig_fidelity_table
// [levels...]
#include <cstdio>
#include <string>
#include <vector>

#include "fixtures/calibration/calibration_procedure.h"
#include "fixtures/calibration/working_volume.h"
#include "host/sensors/tactile/film_field_factory.h"
#include "rig/clock.h"

namespace {

using hilrig::dut_fw::FilmConstants;
using hilrig::host::FilmFieldModel;
using hilrig::host::FilmPose;

constexpr int kGridPoints = 6;

double SecondsPerEvaluation(const FilmFieldModel& film, const std::vector<FilmPose>& poses) {
  const hilrig::rig::SteadyClock clock;
  int evaluations = 0;
  double sink = 0;
  const std::int64_t start_ns = clock.NowNs();
  while (clock.NowNs() - start_ns < 200'000'000 || evaluations < 20) {
    sink += film.FieldAtChip(poses[evaluations % poses.size()]).z();
    ++evaluations;
  }
  if (sink == 12345.678) std::puts("");  // keeps the loop from being optimised away
  return 1e-9 * static_cast<double>(clock.NowNs() - start_ns) / evaluations;
}

Eigen::Vector3d ZeroedS(const FilmFieldModel& film, const FilmConstants<double>& constants,
                        const FilmPose& pose) {
  const auto s = hilrig::dut_fw::ComputeS<double>(constants, film.FieldAtChip(pose));
  const auto rest = hilrig::dut_fw::ComputeS<double>(constants, film.FieldAtChip(FilmPose{}));
  return s.s - rest.s;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> levels = {"tiles:4", "tiles:8", "tiles:16", "tiles:32", "tiles:64",
                                     "map:16",  "map:32",  "opmap:16", "opmap:32"};
  if (argc > 1) levels.assign(argv + 1, argv + argc);
  const auto reference = hilrig::host::MakeFilmField("tiles:128").value();
  const hilrig::fixtures::CalibrationBench bench;
  hilrig::fixtures::CalibrationOptions options;
  options.no_load_samples = 50;
  const auto calibration = hilrig::fixtures::Calibrate(bench, *reference, 1, options);
  const auto constants = hilrig::fixtures::FilmConstantsOf(calibration);
  const Eigen::Vector3d a = hilrig::fixtures::ForceCalibrationOf(calibration.sensors(0)).a;

  std::vector<FilmPose> poses;
  const auto volume = hilrig::fixtures::OperatingVolume(options.limits, bench.tactile[0].silicone);
  for (const Eigen::Vector3d& centre : hilrig::fixtures::GridOver(volume, kGridPoints)) {
    FilmPose pose;
    pose.centre_m = centre;
    poses.push_back(pose);
  }
  std::printf("%-10s %14s %16s %16s\n", "level", "time/eval", "field rel err", "force err (N)");
  for (const std::string& level : levels) {
    const auto film = hilrig::host::MakeFilmField(level);
    if (!film) {
      std::fprintf(stderr, "%s\n", film.error().message.c_str());
      return 2;
    }
    double field_error = 0, force_error_n = 0;
    for (const FilmPose& pose : poses) {
      const Eigen::Vector3d truth = reference->FieldAtChip(pose);
      field_error =
          std::max(field_error, (film.value()->FieldAtChip(pose) - truth).norm() / truth.norm());
      const Eigen::Vector3d ds =
          ZeroedS(*film.value(), constants, pose) - ZeroedS(*reference, constants, pose);
      force_error_n = std::max(force_error_n, a.cwiseProduct(ds).cwiseAbs().maxCoeff());
    }
    std::printf("%-10s %11.3g us %16.2e %16.2e\n", level.c_str(),
                1e6 * SecondsPerEvaluation(*film.value(), poses), field_error, force_error_n);
  }
  return 0;
}
