// The bad-input probe's defects (issue 19), each fed through the binary: exit code, one line
// on stderr, and no output created, replaced or truncated.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_support.hpp"

namespace fvx::test {
namespace {

std::string sample_scan(int view) {
  return std::string(std::getenv("FVX_SOURCE_DIR")) + "/data/sample/box-room/view" + std::to_string(view) + ".pcd";
}

/// A small map of the bundled sample, m.bt in `dir`.
void make_map(const TempDir& dir) {
  const RunResult r = run_fvx(dir, "integrate " + sample_scan(0) + " -o m.bt");
  ASSERT_EQ(r.status, 0) << r.err;
}

void expect_one_line(const RunResult& r, int status, const std::string& words) {
  EXPECT_EQ(r.status, status) << r.err;
  EXPECT_EQ(line_count(r.err), 1u) << r.err;
  EXPECT_NE(r.err.find(words), std::string::npos) << r.err;
}

TEST(Hardening, AnOutputThatIsAnInputIsRefusedAndTheInputKept) {
  const TempDir dir;
  make_map(dir);
  const std::string map = slurp(dir / "m.bt");
  expect_one_line(run_fvx(dir, "voids m.bt -o m.bt"), 2, "--output m.bt is also an input");
  expect_one_line(run_fvx(dir, "voids m.bt -o ./m.bt"), 2, "is also an input");
  std::filesystem::create_symlink("m.bt", dir / "link.bt");
  expect_one_line(run_fvx(dir, "voids link.bt -o m.bt"), 2, "is also an input");
  expect_one_line(run_fvx(dir, "integrate " + sample_scan(1) + " --map m.bt -o m.bt"), 2, "is also an input");
  expect_one_line(run_fvx(dir, "voids m.bt --cloud a.ply --picture a.ply"), 2, "name the same file a.ply");
  EXPECT_TRUE(slurp(dir / "m.bt") == map) << "the input map changed";
  EXPECT_FALSE(std::filesystem::exists(dir / "a.ply"));
}

// `-o /dev/null` run as root replaced the device with a plain file (the output's temporary was
// renamed onto it), and a pipe could not be an output at all. Both are now written into.
TEST(Hardening, DevicesAndPipesAsOutputsAreWrittenIntoNotReplaced) {
  const TempDir dir;
  make_map(dir);
  const RunResult r = run_fvx(dir, "voids m.bt -o /dev/null");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(std::filesystem::is_character_file("/dev/null"));
  ASSERT_EQ(::mkfifo((dir / "p").c_str(), 0600), 0);
  const std::string line = "cd '" + dir.path().string() + "' && { timeout 60 cat p > got.json & '" FVX_BINARY
                           "' voids m.bt -o p; status=$?; wait; exit $status; }";
  const int raw = std::system(line.c_str());
  EXPECT_EQ(WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, 0);
  EXPECT_TRUE(std::filesystem::is_fifo(dir / "p"));
  const auto report = nlohmann::json::parse(slurp(dir / "got.json"));
  EXPECT_TRUE(report["results"].contains("void_clusters")) << report.dump().substr(0, 200);
  // "-" is standard output for a report (it was a file named "-").
  for (const std::string& command : {std::string("voids m.bt -o -"), "integrate " + sample_scan(0) + " -o m2.bt --report -"}) {
    const RunResult dash = run_fvx(dir, command);
    EXPECT_EQ(dash.status, 0) << dash.err;
    EXPECT_TRUE(nlohmann::json::parse(dash.out).contains("results")) << command;
    EXPECT_FALSE(std::filesystem::exists(dir / "-")) << command;
  }
}

TEST(Hardening, EveryOutputIsCheckedBeforeAnyIsWritten) {
  const TempDir dir;
  std::ofstream(dir / "out.bt") << "keep";
  expect_one_line(run_fvx(dir, "integrate " + sample_scan(0) + " -o out.bt --report nope/r.json"), 1,
                  "folder 'nope' does not exist");
  EXPECT_EQ(slurp(dir / "out.bt"), "keep");
  expect_one_line(run_fvx(dir, "integrate " + sample_scan(0) + " -o new.bt --report out.bt/r.json"), 1,
                  "is not a folder");
  EXPECT_FALSE(std::filesystem::exists(dir / "new.bt"));
}

// The README's own `fvx replay session/ -o out/` was refused: "folder 'out' does not exist"
// (a folder output's trailing slash was taken for a file in a folder out).
TEST(Hardening, AFolderOutputMayEndInASlashAndHaveNewParents) {
  const TempDir dir;
  const std::string scans = std::string(std::getenv("FVX_SOURCE_DIR")) + "/data/sample/box-room/view*.pcd";
  const RunResult replay = run_fvx(dir, "replay --scans '" + scans + "' --no-capmap --to 1 -o out/");
  EXPECT_EQ(replay.status, 0) << replay.err;
  EXPECT_TRUE(std::filesystem::is_directory(dir / "out/maps"));
  const std::string arm = std::string(std::getenv("FVX_SOURCE_DIR")) + "/data/arms/fvx-arm.urdf";
  const RunResult plan =
      run_fvx(dir, "batch capmap " + arm + " --base base_link --tip kinect_optical --voxel 0.05 --shards 2 -o a/b/plan/");
  EXPECT_EQ(plan.status, 0) << plan.err;
  EXPECT_TRUE(std::filesystem::is_regular_file(dir / "a/b/plan/tasks.txt"));
  std::ofstream(dir / "file") << "x";
  expect_one_line(run_fvx(dir, "batch capmap " + arm + " --base base_link --tip kinect_optical --voxel 0.05 --shards 2 -o file/plan/"),
                  1, "is not a folder");
}

TEST(Hardening, AReportThatCannotBeWrittenIsAFailure) {
  const TempDir dir;
  make_map(dir);
  const std::string capmap_info = "capmap info " + std::string(std::getenv("FVX_SOURCE_DIR")) + "/data/arms/fvx-arm.fcm";
  for (const std::string& command : {std::string("voids m.bt"), std::string("frontiers m.bt"), capmap_info}) {
    const std::string line = "cd '" + dir.path().string() + "' && '" FVX_BINARY "' " + command + " > /dev/full 2> err.txt";
    const int raw = std::system(line.c_str());
    EXPECT_EQ(WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, 1) << command;
    EXPECT_NE(slurp(dir / "err.txt").find("cannot write the report to standard output"), std::string::npos) << command;
  }
}

// A disk that fills up while fvx writes, made with a file size limit (writes past it fail
// with EFBIG, as on a full disk with ENOSPC; SIGXFSZ ignored so that the write fails instead
// of the process dying): one line naming the file and why, exit 1, and nothing left behind,
// not even the temporary beside the output. PCL threw from its writer here, which reached the
// user as "unexpected error: [pcl::PCDWriter::writeBinary] Error during raw_fallocate ()!".
// Exit 1 and one line for maps, clouds (PCD, PLY), reports and pictures.
TEST(Hardening, AFullDiskIsNamedOnOneLineAndLeavesNoFile) {
  const TempDir dir;
  make_map(dir);
  const std::string full = "trap '' XFSZ; ulimit -f 4; ";  // 2 KiB in sh's 512-byte blocks
  auto files = [&] {
    std::vector<std::string> names;
    for (const auto& entry : std::filesystem::directory_iterator(dir.path())) names.push_back(entry.path().filename());
    std::sort(names.begin(), names.end());
    return names;
  };
  const std::vector<std::string> before = files();
  expect_one_line(run_fvx(dir, "simulate builtin:crates --look-at 0.1,0,0.9,0.8,0,0.15 -o a.pcd", full), 1,
                  "a.pcd: cannot write PCD: no room for the file");
  expect_one_line(run_fvx(dir, "integrate " + sample_scan(0) + " -o n.bt", full), 1,
                  "n.bt: cannot write the map: File too large");
  expect_one_line(run_fvx(dir, "voids m.bt --cloud v.pcd", full), 1, "v.pcd: cannot write PCD: no room for the file");
  expect_one_line(run_fvx(dir, "voids m.bt -o v.json", full), 1, "v.json: cannot write: File too large");
  expect_one_line(run_fvx(dir, "voids m.bt --cloud v.ply", full), 1, "v.ply: cannot write: File too large");
  // libpng printed "libpng error: Write Error" on a line of its own before this one.
  expect_one_line(run_fvx(dir, "voids m.bt --picture p.png", full), 1, "p.png: cannot write the PNG: File too large");
  EXPECT_EQ(files(), before);
}

TEST(Hardening, PipesAndDevicesAreNotReadAsFiles) {
  const TempDir dir;
  ASSERT_EQ(::mkfifo((dir / "pipe.bt").c_str(), 0600), 0);
  // Without the check, opening the pipe waits for a writer forever: `timeout` turns that into 124.
  expect_one_line(run_fvx(dir, "voids pipe.bt", "timeout 60"), 1, "pipe.bt: is not a regular file");
  expect_one_line(run_fvx(dir, "capmap info /dev/zero", "timeout 60"), 1, "/dev/zero: is not a regular file");
  expect_one_line(run_fvx(dir, "integrate " + sample_scan(0) + " --trajectory /dev/zero -o m.bt", "timeout 60"), 1,
                  "/dev/zero: is not a regular file");
  EXPECT_FALSE(std::filesystem::exists(dir / "m.bt"));
}

TEST(Hardening, AUrdfWhoseLinksFormACycleIsRefused) {
  const TempDir dir;
  std::ofstream(dir / "cycle.urdf") << R"(<robot name="c"><link name="a"/><link name="b"/><link name="c"/>
    <joint name="j1" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/>
      <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
    <joint name="j2" type="revolute"><parent link="b"/><child link="c"/><axis xyz="0 1 0"/>
      <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
    <joint name="j3" type="revolute"><parent link="c"/><child link="b"/><axis xyz="0 1 0"/>
      <limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>)";
  expect_one_line(run_fvx(dir, "capmap build cycle.urdf --base a --tip c -o c.fcm", "timeout 60"), 1,
                  "cycle.urdf: the joints' links form a cycle (through link 'b')");
  EXPECT_FALSE(std::filesystem::exists(dir / "c.fcm"));
}

/// A PCD header with these SIZE, WIDTH (= POINTS), VIEWPOINT and DATA lines, then `data`.
std::string pcd(const std::string& size, const std::string& width, const std::string& viewpoint,
                const std::string& encoding, const std::string& data) {
  return "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE " + size + "\nTYPE F F F\nCOUNT 1 1 1\nWIDTH " + width +
         "\nHEIGHT 1\nVIEWPOINT " + viewpoint + "\nPOINTS " + width + "\nDATA " + encoding + "\n" + data;
}

// Each lying or malformed cloud header: one line naming the field, exit 1, no map written,
// in well under the seconds and gigabytes the probe saw (a 60 s timeout would turn a hang
// into 124).
TEST(Hardening, CloudHeadersThatLieAreRefusedBeforeAnythingIsAllocated) {
  const TempDir dir;
  const std::string identity = "0 0 0 1 0 0 0";
  const std::string binary_sizes("\x10\x00\x00\x00\xf0\xff\xff\xff" "0123456789abcdef", 24);
  const std::vector<std::pair<std::string, std::string>> cases = {
      {pcd("4 4 4", "-5", identity, "ascii", "1 2 3\n"), "WIDTH '-5' is not a count"},
      {pcd("4 4 4", "2000000000", identity, "ascii", "1 2 3\n"), "POINTS 2000000000 is more than the ascii data can hold"},
      {pcd("4 4 4", "2000000000", identity, "binary", "0123456789ab"), "truncated point data: header promises 2000000000"},
      {pcd("4 4 4", "100", identity, "binary_compressed", binary_sizes), "binary_compressed block unpacks to 4294967280"},
      {pcd("4 4 4", "3", identity, "ascii", "a b c\nx y z\n1 2 3\n"), "data line 1: 'a' is not a number"},
      {pcd("4 4 4", "2", identity, "ascii", "1 2 3\n4 5\n"), "data line 2 has 2 values"},
      {pcd("4 4 4", "1", "nan 0 0 1 0 0 0", "ascii", "1 2 3\n"), "VIEWPOINT ' nan 0 0 1 0 0 0' is not seven finite"},
      {pcd("2 2 2", "1", identity, "ascii", "1 2 3\n"), "field x: TYPE F with SIZE 2 is not a PCD type"},
      {pcd("4 4 4", "0", identity, "binary", ""), "the scan holds no points"},
      {"ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\nproperty float y\n"
       "property float z\nend_header\n", "element vertex '4000000000' is not a count"},
      {"ply\nformat ascii 1.0\nelement vertex -3\nproperty float x\nproperty float y\nproperty float z\nend_header\n"
       "1 2 3\n", "element vertex '-3' is not a count"},
      {"ply\nformat binary_little_endian 1.0\nelement vertex 1000\nproperty float x\nproperty float y\n"
       "property float z\nend_header\n0123", "truncated PLY data"},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const std::string name = "c" + std::to_string(i) + (cases[i].first.rfind("ply", 0) == 0 ? ".ply" : ".pcd");
    std::ofstream(dir / name, std::ios::binary) << cases[i].first;
    expect_one_line(run_fvx(dir, "integrate " + name + " -o m.bt", "timeout 60"), 1, name + ": " + cases[i].second);
    EXPECT_FALSE(std::filesystem::exists(dir / "m.bt")) << name;
  }
  // The same headers telling the truth are read.
  std::ofstream(dir / "ok.pcd") << pcd("4 4 4", "3", identity, "ascii", "1 2 3\nnan nan nan\n1 2 3.5\n");
  std::ofstream(dir / "ok.ply") << "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                                   "property float z\nend_header\n1 2 3\n4 5 6\n";
  for (const char* ok : {"ok.pcd", "ok.ply"}) {
    const RunResult r = run_fvx(dir, std::string("integrate ") + ok + " --pose 0,0,0,0,0,0,1 -o ok.bt");
    EXPECT_EQ(r.status, 0) << ok << ": " << r.err;
  }
}

// Intrinsics files are held to the command line's limits: a width of 1e9 sized an image of
// gigabytes, 1e30 was converted to an int unchecked.
TEST(Hardening, IntrinsicsFilesAreHeldToTheCommandLinesLimits) {
  const TempDir dir;
  const std::string scene = std::string(std::getenv("FVX_SOURCE_DIR")) + "/data/scenes/crates.ply";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {R"({"fx":525,"fy":525,"cx":319.5,"cy":239.5,"width":1000000000,"height":480})", "'width' must be 1 to 16384 pixels"},
      {R"({"fx":525,"fy":525,"cx":319.5,"cy":239.5,"width":640,"height":1e30})", "'height' must be 1 to 16384 pixels"},
      {R"({"fx":5e9,"fy":525,"cx":319.5,"cy":239.5,"width":640,"height":480})", "fx must be a non-zero focal length"},
  };
  for (const auto& [intrinsics, words] : cases) {
    std::ofstream(dir / "k.json") << intrinsics;
    expect_one_line(run_fvx(dir, "simulate " + scene + " --look-at 0,-1.5,1,0.5,0,0.3 --intrinsics k.json -o x.pcd",
                            "timeout 60"),
                    1, "k.json: " + words);
    EXPECT_FALSE(std::filesystem::exists(dir / "x.pcd"));
  }
}

// OctoMap's readers recurse without a depth or node limit: one flipped bit in a child mask of
// a .ot made fvx read for 20 s into gigabytes. Maps whose node stream does not hold together
// are refused in milliseconds, with one line.
TEST(Hardening, OctreeFilesWhoseNodesDoNotHoldTogetherAreRefused) {
  const TempDir dir;
  ASSERT_EQ(run_fvx(dir, "integrate " + sample_scan(0) + " -o s.ot").status, 0);
  ASSERT_EQ(run_fvx(dir, "integrate " + sample_scan(0) + " -o s.bt").status, 0);
  std::string chain = "# Octomap OcTree file\nid OcTree\nsize 18\nres 0.1\ndata\n";
  for (int depth = 0; depth < 18; ++depth) chain += std::string(4, '\0') + "\x01";  // one child each, 18 deep
  std::ofstream(dir / "deep.ot", std::ios::binary) << chain;
  expect_one_line(run_fvx(dir, "voids deep.ot", "timeout 60"), 1, "deep.ot: corrupt OctoMap data: a node below depth 16");
  const std::string bt = slurp(dir / "s.bt");
  std::ofstream(dir / "half.bt", std::ios::binary) << bt.substr(0, bt.size() / 2);
  expect_one_line(run_fvx(dir, "voids half.bt", "timeout 60"), 1, "half.bt: truncated or corrupt OctoMap data");
  // Single flipped bits anywhere in the node data: read or refused, never a hang or a crash.
  const std::string ot = slurp(dir / "s.ot");
  const std::size_t data = ot.find("data\n") + 5;
  std::mt19937_64 rng(5);
  int refused = 0;
  for (int trial = 0; trial < 60; ++trial) {
    std::string flipped = ot;
    flipped[data + rng() % (ot.size() - data)] ^= char(1 << (rng() % 8));
    std::ofstream(dir / "f.ot", std::ios::binary) << flipped;
    const RunResult r = run_fvx(dir, "voids f.ot", memory_limit() + "timeout 60");
    EXPECT_TRUE(r.status == 0 || (r.status == 1 && line_count(r.err) == 1)) << trial << ": " << r.status << " " << r.err;
    refused += r.status == 1;
  }
  EXPECT_GT(refused, 10);
}

// A scene sidecar whose search space no map can hold aborted fvx simulate (exit 134, an
// assertion in the ground truth or in Embree) after the scan was written. Now one line, and
// neither the scan nor the ground truth is written.
TEST(Hardening, ASearchSpaceNoMapCanHoldIsRefusedBeforeAnyScan) {
  const TempDir dir;
  const std::string scene = std::string(std::getenv("FVX_SOURCE_DIR")) + "/data/scenes/crates.ply";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"[-1e6, -1e6, -1e6], \"max\": [1e6, 1e6, 1e6]", "s.json: search_space.min must lie within ±10000 m"},
      {"[-1e308, 0, 0], \"max\": [1e308, 1, 1]", "s.json: search_space.min must lie within ±10000 m"},
      {"[-5000, 0, 0], \"max\": [5000, 1, 1]", "the search space reaches beyond ±819 m, the most a map of 0.025 m"},
  };
  for (const auto& [box, words] : cases) {
    std::ofstream(dir / "s.json") << "{\"search_space\": {\"min\": " + box + "}}";
    expect_one_line(run_fvx(dir, "simulate " + scene + " --scene-info s.json --look-at 0,-1.5,1,0.5,0,0.3 -o x.pcd "
                                 "--ground-truth gt.bt", "timeout 60"),
                    1, words);
    EXPECT_FALSE(std::filesystem::exists(dir / "x.pcd"));
    EXPECT_FALSE(std::filesystem::exists(dir / "gt.bt"));
  }
}

// A depth image whose every pixel is the saturated 65535 ran 112 s into 1.4 GB and exited 0
// (300 000 rays of 65 m). 65535 is no measurement, as 0 is: the scan holds no points.
TEST(Hardening, SaturatedDepthPixelsAreNoMeasurement) {
  const TempDir dir;
  const auto pgm = [&](const std::string& name, int valid) {  // 640x480, 16-bit big-endian
    std::string pixels;
    for (int i = 0; i < 640 * 480; ++i) {
      const unsigned d = i >= 240 * 640 + 200 && i < 240 * 640 + 200 + valid ? 1500u : 65535u;
      pixels += char(d >> 8);
      pixels += char(d & 0xff);
    }
    std::ofstream(dir / name, std::ios::binary) << "P5\n640 480\n65535\n" << pixels;
  };
  pgm("saturated.pgm", 0);
  pgm("forty.pgm", 40);
  const std::string K = " --fx 525 --fy 525 --cx 319.5 --cy 239.5 --pose 0,0,0,0,0,0,1 -o m.bt";
  expect_one_line(run_fvx(dir, "integrate saturated.pgm" + K, "timeout 60"), 1, "saturated.pgm: the scan holds no finite points");
  EXPECT_FALSE(std::filesystem::exists(dir / "m.bt"));
  const RunResult r = run_fvx(dir, "integrate forty.pgm" + K, "timeout 60");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out)["results"]["scans"][0]["points"]["kept"], 40);
}

// A 40-byte PNG could ask OpenCV for gigabytes; libpng printed its complaints before fvx's
// line; an image of another size than the intrinsics file states was only warned about.
TEST(Hardening, DepthImagesAreCheckedBeforeDecodingAndAgainstTheIntrinsics) {
  const TempDir dir;
  const std::string seeds = std::string(std::getenv("FVX_SOURCE_DIR")) + "/tests/fuzz/corpus/fuzz_depth_image/";
  const std::string png = slurp(seeds + "depth.png"), pgm = slurp(seeds + "depth.pgm");  // 8x6
  const auto with_size = [&](unsigned width, unsigned height) {
    std::string b = png;
    for (int i = 0; i < 4; ++i) b[std::size_t(16 + i)] = char(width >> (24 - 8 * i)), b[std::size_t(20 + i)] = char(height >> (24 - 8 * i));
    return b;
  };
  std::string flipped = png;
  flipped[png.size() - 20] ^= 0x5a;  // inside the compressed pixels
  const std::vector<std::pair<std::string, std::string>> cases = {
      {with_size(60000, 60000), "PNG width 60000 is not 1 to 16384 pixels"},
      {with_size(16000, 16000), "PNG of 16000x16000 pixels is larger than 2^26 pixels"},
      {flipped, "unreadable PNG (corrupt or cut short)"},
      {pgm.substr(0, pgm.size() - 40), "unreadable PGM (corrupt or cut short)"},
      {std::string("II*\0\xff\xff\xff\x0f", 8), "TIFF directory offset 268435455 is past the end"},
      {"\xff\xd8\xff\xe0 JFIF", "not a PNG, PGM or TIFF image"},
  };
  const std::string K = " --fx 5 --fy 5 --cx 3.5 --cy 2.5 --pose 0,0,0,0,0,0,1 -o m.bt";
  for (const auto& [bytes, words] : cases) {
    std::ofstream(dir / "d.png", std::ios::binary) << bytes;
    expect_one_line(run_fvx(dir, "integrate d.png" + K, memory_limit() + "timeout 60"), 1, "d.png: " + words);
    EXPECT_FALSE(std::filesystem::exists(dir / "m.bt"));
  }
  std::ofstream(dir / "d.pgm", std::ios::binary) << pgm;
  std::ofstream(dir / "k.json") << R"({"fx":525,"fy":525,"cx":319.5,"cy":239.5,"width":640,"height":480})";
  expect_one_line(run_fvx(dir, "integrate d.pgm -K k.json --pose 0,0,0,0,0,0,1 -o m.bt"), 1, "d.pgm: the image is 8x6 but the intrinsics say 640x480");
  EXPECT_FALSE(std::filesystem::exists(dir / "m.bt"));
  const RunResult r = run_fvx(dir, "integrate d.pgm" + K);  // no size stated: the image's
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.err.find("intrinsics say"), std::string::npos) << "no size was stated: " << r.err;
}

// A replay whose first scan failed left an output folder with empty maps/ and reports/.
TEST(Hardening, AReplayThatFailsAtItsFirstViewLeavesNoFolder) {
  const TempDir dir;
  std::ofstream(dir / "t.txt") << "0 0 1 0 0 0 1\n";
  std::ofstream(dir / "a.pcd") << "garbage";
  expect_one_line(run_fvx(dir, "replay --scans a.pcd --trajectory t.txt --format json -o out"), 1,
                  "a.pcd: corrupt PCD header: 'garbage' before DATA; nothing was written");
  EXPECT_FALSE(std::filesystem::exists(dir / "out"));
}

// Every input the fuzz campaigns found (tests/fuzz/corpus/<harness>/found-*) goes through the
// binary: one line and exit 1, no crash and no output. A PLY whose vertices had a list
// property made PCL's reader abort (exit 134); a .bt whose data line was the file's last
// made the node walk index past the string; a .bt with "res 0.4data" was walked from
// another offset than OctoMap reads (OctoMap then recursed past the stack); PCL's PCD header
// parser threw out_of_range ("unexpected error"); a JSON key with a newline split the line;
// a URDF ending in a cut-short UTF-8 character made TinyXML read past it (ASan).
TEST(Hardening, EveryFuzzFindingIsRefusedOnOneLine) {
  const TempDir dir;
  const std::filesystem::path corpus = std::filesystem::path(std::getenv("FVX_SOURCE_DIR")) / "tests/fuzz/corpus";
  const std::map<std::string, std::string> command_of = {
      {"fuzz_pcd", "integrate {} -o m.bt"}, {"fuzz_ply", "integrate {} -o m.bt"},
      {"fuzz_depth_image", "integrate {} --fx 5 --fy 5 --cx 3.5 --cy 2.5 -o m.bt"},
      {"fuzz_json", "integrate " + sample_scan(0) + " -K {} -o m.bt"},
      {"fuzz_octree", "voids {}"}, {"fuzz_fcm", "capmap info {}"},
      {"fuzz_urdf", "capmap build {} BASE TIP --voxel 0.5 --directions 8 -o m.fcm"},
      {"fuzz_bag", "integrate --bag {} --topic /depth --fixed-frame odom --fx 525 --fy 525 --cx 0.5 --cy 0 -o m.bt"}};
  int found = 0;
  for (const auto& harness : std::filesystem::directory_iterator(corpus)) {
    for (const auto& file : std::filesystem::directory_iterator(harness.path())) {
      if (file.path().filename().string().rfind("found-", 0) != 0) continue;
      const auto command = command_of.find(harness.path().filename().string());
      ASSERT_NE(command, command_of.end()) << "no command for " << file.path();
      std::string name = "input" + file.path().extension().string(), line = command->second;
      std::string bytes = slurp(file.path());
      if (command->first == "fuzz_urdf") {  // line 1 names the base and the tip link
        const std::size_t eol = bytes.find('\n'), space = bytes.find(' ');
        line.replace(line.find("BASE TIP"), 8, "--base " + bytes.substr(0, space) + " --tip " + bytes.substr(space + 1, eol - space - 1));
        bytes.erase(0, eol + 1);
        name = "input.urdf";
      }
      std::ofstream(dir / name, std::ios::binary) << bytes;
      line.replace(line.find("{}"), 2, name);
      SCOPED_TRACE(file.path().string());
      expect_one_line(run_fvx(dir, line, memory_limit() + "timeout 60"), 1, name + ": ");
      EXPECT_FALSE(std::filesystem::exists(dir / "m.bt") || std::filesystem::exists(dir / "m.fcm"));
      ++found;
    }
  }
  EXPECT_GE(found, 6);
}

}  // namespace
}  // namespace fvx::test
