// The device verbs end to end: mock-device, send, status, devices.
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "tests/devices/background_wearknit.hpp"
#include "tests/devices/device_test_support.hpp"
#include "tests/test_support.hpp"

namespace devices {
namespace {

using wearknit::test::run_wearknit;

class CliDevicesTest : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = wearknit::test::make_temp_dir("wk-cli-dev"); }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string path(const std::string& name) const { return "'" + (dir_ / name).string() + "'"; }
  std::filesystem::path dir_;
};

TEST_F(CliDevicesTest, TheDoneWhenCommandsStoreTheDatIdenticalAndKnitEveryRowOnce) {
  WEARKNIT_REQUIRE_SHARED(shared);
  std::filesystem::copy_file(
      shared / "corpus" / "dat-reference" / "gen-intarsia-4color-200x200.dat", dir_ / "J.dat");
  test::BackgroundWearknit mock("mock-device --listen tcp://127.0.0.1:0 --store " + path("D") +
                                " --fault corrupt=0.01,drop=0.01,dup=0.01,disconnect-every=500"
                                " --exit-when-done --no-sync --rows-per-s 5000");
  ASSERT_EQ(mock.first_line().rfind("listening tcp://127.0.0.1:", 0), 0u) << mock.first_line();
  const auto sent = run_wearknit("send " + path("J.dat") + " --to " + mock.uri());
  EXPECT_EQ(sent.exit_code, 0) << sent.err;
  auto job = load_job(dir_ / "J.dat");
  ASSERT_TRUE(job.ok());
  const std::string rows = std::to_string(job.value().row_count());
  EXPECT_NE(sent.out.find("done: J.dat -> " + mock.uri() + ": " + rows + "/" + rows +
                          " rows knitted (device confirmed)"),
            std::string::npos)
      << sent.out;
  EXPECT_NE(sent.out.find("progress: "), std::string::npos);  // plain lines: not a terminal
  const std::string log = mock.finish();
  EXPECT_NE(log.find("job J.dat: done: knitted " + rows + "/" + rows + " rows, each exactly once"),
            std::string::npos)
      << log;
  EXPECT_EQ(test::read_text(dir_ / "D" / "J.dat"), test::read_text(dir_ / "J.dat"));
  EXPECT_NE(test::read_text(dir_ / "D" / "J.dat.manifest.json").find(to_hex(job.value().sha256)),
            std::string::npos);
}

TEST_F(CliDevicesTest, AYarnBreakStopsTheJobUntilStatusContinues) {
  wearknit::test::write_file(dir_ / "a.k", test::sheet_knitout(6, 40));
  test::BackgroundWearknit mock("mock-device --listen tcp://127.0.0.1:0 --store " + path("D") +
                                " --fault yarn-break-at=10 --exit-when-done --no-sync"
                                " --rows-per-s 400");
  ASSERT_FALSE(mock.uri().empty()) << mock.first_line();
  test::BackgroundWearknit send("send -q " + path("a.k") + " --to " + mock.uri());
  std::string status;
  for (int i = 0; i < 200; ++i) {
    status = run_wearknit("status --json --to " + mock.uri()).out;
    if (status.find("\"state\": \"alarm\"") != std::string::npos) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_NE(status.find("\"alarm\": \"yarn break\""), std::string::npos) << status;
  EXPECT_NE(status.find("\"rows_knitted\": 10,"), std::string::npos) << status;
  const auto resumed = run_wearknit("status --continue --to " + mock.uri());
  EXPECT_EQ(resumed.exit_code, 0) << resumed.err;
  const std::string sent = send.first_line() + "\n" + send.finish();
  EXPECT_NE(sent.find("wearknit send: the machine stopped (yarn break) after row 10 of 42; clear "
                      "it and run `wearknit status --to " +
                      mock.uri() + " --continue`"),
            std::string::npos)
      << sent;
  EXPECT_NE(sent.find("done: a.k -> " + mock.uri() + ": 42/42 rows knitted"), std::string::npos)
      << sent;
  EXPECT_NE(mock.finish().find("job a.k: done: knitted 42/42 rows, each exactly once"),
            std::string::npos);
}

TEST_F(CliDevicesTest, SendToAFolderWritesReadsBackAndLeavesAManifest) {
  const std::string text = test::sheet_knitout(8, 6);
  wearknit::test::write_file(dir_ / "s.k", text);
  std::filesystem::create_directories(dir_ / "stick");
  const auto r = run_wearknit("send " + path("s.k") + " --to dir:" + (dir_ / "stick").string());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.rfind("stored " + (dir_ / "stick").string() + "/s.k (", 0), 0u) << r.out;
  EXPECT_EQ(test::read_text(dir_ / "stick" / "s.k"), text);
  EXPECT_TRUE(std::filesystem::exists(dir_ / "stick" / "s.k.manifest.json"));
  const auto missing =
      run_wearknit("send " + path("s.k") + " --to dir:" + (dir_ / "nope").string());
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_EQ(missing.err, "wearknit send: dir:" + (dir_ / "nope").string() +
                             ": no such folder (is the stick mounted?)\n");
}

TEST_F(CliDevicesTest, LoopbackSendThenStatusShowsTheJobDone) {
  wearknit::test::write_file(dir_ / "s.k", test::sheet_knitout(6, 10));
  const std::string uri = "loopback:" + (dir_ / "lb").string();
  const auto r = run_wearknit("send " + path("s.k") + " --to " + uri);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  const auto s = run_wearknit("status --to " + uri);
  EXPECT_EQ(s.exit_code, 0) << s.err;
  EXPECT_NE(s.out.find("job 's.k' (knitout, sha256 "), std::string::npos) << s.out;
  EXPECT_NE(s.out.find("): done, 12/12 rows knitted, 12/12 received\n"), std::string::npos)
      << s.out;
  const auto j = run_wearknit("status --json --to " + uri);
  EXPECT_NE(j.out.find("\"state\": \"done\""), std::string::npos) << j.out;
  const auto pause = run_wearknit("status --pause --to " + uri);
  EXPECT_EQ(pause.exit_code, 1);
  EXPECT_EQ(pause.err,
            "wearknit status: " + uri + ": no unfinished job to pause (the device is done)\n");
}

TEST_F(CliDevicesTest, TwoSendersToOneLoopbackMachineTakeTurns) {
  // Two processes send to the same loopback store at once. The machine
  // serves one at a time, so neither job is spooled into the other's files.
  wearknit::test::write_file(dir_ / "a.k", test::sheet_knitout(60, 400));
  wearknit::test::write_file(dir_ / "b.k", test::sheet_knitout(50, 500));
  const std::string uri = "loopback:" + (dir_ / "lb2").string();
  std::string command;
  for (const char* name : {"a", "b"}) {
    command += "('" + wearknit::test::wearknit_binary() + "' send -q " +
               path(std::string(name) + ".k") + " --to " + uri + " 2>" +
               path(std::string(name) + ".err") + "; echo $? >" + path(std::string(name) + ".rc") +
               ") & ";
  }
  command += "wait";
  ASSERT_EQ(std::system(command.c_str()), 0);
  for (const char* name : {"a", "b"}) {
    const std::string file = std::string(name) + ".k";
    EXPECT_EQ(test::read_text(dir_ / (std::string(name) + ".rc")), "0\n")
        << test::read_text(dir_ / (std::string(name) + ".err"));
    EXPECT_TRUE(test::read_text(dir_ / "lb2" / file) == test::read_text(dir_ / file))
        << file << " is not stored as it was sent";
  }
}

TEST_F(CliDevicesTest, AnInvalidJobIsRefusedByTheDeviceWithTheReason) {
  // Syntax: the parser's K code.
  wearknit::test::write_file(dir_ / "bad.k", ";!knitout-2\n;;Carriers: 1 2 3\nknot + f1 3\n");
  const auto r =
      run_wearknit("send -q " + path("bad.k") + " --to loopback:" + (dir_ / "lb").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.err, "wearknit send: " + (dir_ / "bad.k").string() +
                       ": the device refused the job: bad.k:3:1: error: [K010] unknown "
                       "operation 'knot'\n");
  EXPECT_FALSE(std::filesystem::exists(dir_ / "lb" / "bad.k"));
  // Semantics: the needle-bed virtual machine's V code.
  wearknit::test::write_file(dir_ / "sem.k", ";!knitout-2\n;;Carriers: 1 2 3\nknit + f1 3\n");
  const auto v =
      run_wearknit("send -q " + path("sem.k") + " --to loopback:" + (dir_ / "lb").string());
  EXPECT_EQ(v.exit_code, 1);
  EXPECT_EQ(v.err, "wearknit send: " + (dir_ / "sem.k").string() +
                       ": the device refused the job: sem.k:3: error: [V004] carrier '3' is not "
                       "in; bring it in with in or inhook before using it\n");
  EXPECT_FALSE(std::filesystem::exists(dir_ / "lb" / "sem.k"));
}

TEST_F(CliDevicesTest, ADatTheReaderCannotLayOutIsRefused) {
  // Rows add up (10 pixels each), so only the DAT reader can object.
  std::string dat(0x600, '\0');
  dat[4] = 9;  // width 10
  dat[6] = 1;  // height 2
  dat += std::string("\0\x0a\0\x0a", 4);
  wearknit::test::write_file(dir_ / "tiny.dat", dat);
  const auto r =
      run_wearknit("send -q " + path("tiny.dat") + " --to loopback:" + (dir_ / "lb").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.err, "wearknit send: " + (dir_ / "tiny.dat").string() +
                       ": the device refused the job: tiny.dat: error: [D046] a 10 x 2 raster "
                       "is too small for the swg091n2 layout (at least 111 x 19)\n");
}

TEST_F(CliDevicesTest, AValidTwinOfTheRefusedJobIsKnitted) {
  wearknit::test::write_file(dir_ / "good.k",
                             ";!knitout-2\n;;Carriers: 1 2 3\ninhook 3\nknit + f1 3\n"
                             "releasehook 3\nouthook 3\n");
  const auto r =
      run_wearknit("send -q " + path("good.k") + " --to loopback:" + (dir_ / "lb").string());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(std::filesystem::exists(dir_ / "lb" / "good.k"));
}

TEST_F(CliDevicesTest, UsageErrorsSayWhatIsWrong) {
  const auto fault = run_wearknit("mock-device --listen tcp://127.0.0.1:0 --store " + path("D") +
                                  " --fault drop=2");
  EXPECT_EQ(fault.exit_code, 2);
  EXPECT_EQ(fault.err,
            "wearknit mock-device: --fault: fault drop=2: the value must be a probability from 0 "
            "to 1\n");
  const auto uri = run_wearknit("send x.k --to ftp://host");
  EXPECT_EQ(uri.exit_code, 2);
  EXPECT_EQ(uri.err,
            "wearknit send: device URI 'ftp://host': expected tcp://HOST:PORT, serial:PATH, "
            "usb://VID:PID, dir:PATH or loopback:\n");
  wearknit::test::write_file(dir_ / "notes.txt", "hello");
  const auto format = run_wearknit("send " + path("notes.txt") + " --to loopback:");
  EXPECT_EQ(format.exit_code, 1);
  EXPECT_EQ(format.err, "wearknit send: " + (dir_ / "notes.txt").string() +
                            ": not a DAT (.dat) or knitout (.k) job: cannot tell its rows\n");
  const auto usb = run_wearknit("mock-device --listen usb://1209:4b4e --store " + path("D"));
  EXPECT_EQ(usb.exit_code, 2);
}

TEST_F(CliDevicesTest, OnATerminalSendDrawsAProgressBar) {
  if (std::system("command -v script >/dev/null 2>&1") != 0) {
    GTEST_SKIP() << "needs util-linux `script` to give send a terminal";
  }
  wearknit::test::write_file(dir_ / "t.k", test::sheet_knitout(6, 10));
  // `script` runs send with a pseudo-terminal as its stdout.
  const auto r = wearknit::test::run_wearknit(
      "--version >/dev/null; script -qec \"'" + wearknit::test::wearknit_binary() + "' send " +
      path("t.k") + " --to loopback:" + (dir_ / "lb").string() + "\" /dev/null");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("\r[##############################] 12/12 rows knitted (12 received) done"),
            std::string::npos)
      << r.out;
  EXPECT_EQ(r.out.find("progress: "), std::string::npos) << r.out;  // no plain lines
}

TEST_F(CliDevicesTest, DeviceDebugTracesFramesAndDecisions) {
  wearknit::test::write_file(dir_ / "d.k", test::sheet_knitout(4, 4));
  const auto r = wearknit::test::run_wearknit(
      "--version >/dev/null; WEARKNIT_DEVICE_DEBUG=1 '" + wearknit::test::wearknit_binary() +
      "' send -q " + path("d.k") + " --to loopback:" + (dir_ / "lb").string());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find(" host -> HELLO job=0 seq=1 len=6\n"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(" device: job d.k: manifest accepted (knitout, "), std::string::npos);
  EXPECT_NE(r.err.find(" host <- STATUS job="), std::string::npos);
  EXPECT_EQ(r.err.rfind("wearknit-dev: ", 0), 0u);
  const auto quiet =
      run_wearknit("send -q " + path("d.k") + " --to loopback:" + (dir_ / "lb2").string());
  EXPECT_EQ(quiet.err, "");
}

TEST_F(CliDevicesTest, DevicesListsSerialPortsAndUsbDevices) {
  const auto r = run_wearknit("devices");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.rfind("serial ports:\n", 0), 0u) << r.out;
  EXPECT_NE(r.out.find("\nUSB devices:\n"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace devices
