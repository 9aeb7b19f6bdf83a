// .npy writer and reader: exact round trip, the header layout NumPy expects, strict rejection of
// everything that is not a float32 C-order 2D array, and a cross-check with NumPy itself.
#include "host/io/npy.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <string>

namespace ardcell {
namespace {

namespace fs = std::filesystem;

class NpyTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("ardcell_npy_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  static std::vector<uint8_t> bytes_of(const std::string& s) { return {s.begin(), s.end()}; }
  static std::string npy_with_dict(const std::string& dict, std::size_t data_bytes) {
    std::string d = dict;
    d.push_back('\n');
    std::string out("\x93NUMPY\x01\x00", 8);
    out.push_back(char(d.size() & 0xff));
    out.push_back(char(d.size() >> 8));
    return out + d + std::string(data_bytes, '\0');
  }
  static Status parse(const std::string& file, NpyArray& out) {
    return parse_npy(bytes_of(file), "x.npy", out);
  }
  std::size_t file_count() const {
    return std::size_t(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()));
  }
  fs::path dir_;
};

TEST_F(NpyTest, HeaderIsVersion1AlignedTo64AndEndsWithNewline) {
  for (auto [ny, nx] : {std::pair{1, 1}, {256, 256}, {12345, 7}}) {
    const std::string h = npy_header(ny, nx);
    EXPECT_EQ(h.size() % 64, 0u);
    EXPECT_EQ(h.substr(0, 8), std::string("\x93NUMPY\x01\x00", 8));
    EXPECT_EQ(std::size_t(uint8_t(h[8])) | std::size_t(uint8_t(h[9])) << 8, h.size() - 10);
    EXPECT_EQ(h.back(), '\n');
    EXPECT_NE(h.find("'descr': '<f4', 'fortran_order': False, 'shape': (" + std::to_string(ny) +
                     ", " + std::to_string(nx) + "), }"),
              std::string::npos);
  }
}

TEST_F(NpyTest, RoundTripOfAFieldInteriorIsBitExactAndLeavesNoTemporary) {
  FieldF f({37, 21}, 2);
  for (int y = -2; y < 23; ++y)
    for (int x = -2; x < 39; ++x) f(x, y) = float(x) * 0.37f - float(y) * 1.5e-3f + 1e-30f * x;
  f(3, 4) = -0.0f;
  f(5, 6) = std::numeric_limits<float>::denorm_min();
  const fs::path path = dir_ / "u.npy";
  ASSERT_TRUE(write_npy(path, f.view(f.interior())));
  EXPECT_EQ(file_count(), 1u);  // the temporary was renamed, not left next to it
  EXPECT_EQ(fs::file_size(path), npy_header(21, 37).size() + 21 * 37 * 4);
  NpyArray a;
  Status s = read_npy(path, a);
  ASSERT_TRUE(s) << s.message();
  ASSERT_EQ(a.ny, 21);
  ASSERT_EQ(a.nx, 37);
  for (int y = 0; y < 21; ++y)
    for (int x = 0; x < 37; ++x)
      ASSERT_EQ(std::memcmp(&a.data[std::size_t(y) * 37 + x], &f(x, y), 4), 0) << x << "," << y;
  FieldF g({37, 21}, 1);
  ASSERT_TRUE(read_npy_into(path, g));
  for (int y = 0; y < 21; ++y)
    for (int x = 0; x < 37; ++x) ASSERT_EQ(g(x, y), f(x, y));
}

TEST_F(NpyTest, ReadIntoAFieldOfAnotherSizeSaysBoth) {
  FieldF f({4, 3}, 1);
  ASSERT_TRUE(write_npy(dir_ / "a.npy", f.view(f.interior())));
  FieldF g({3, 4}, 1);
  Status s = read_npy_into(dir_ / "a.npy", g);
  ASSERT_FALSE(s);
  EXPECT_NE(s.message().find("(3, 4)"), std::string::npos) << s.message();
  EXPECT_NE(s.message().find("(4, 3)"), std::string::npos) << s.message();
}

TEST_F(NpyTest, AcceptsReorderedKeysVersion2AndNoTrailingComma) {
  NpyArray a;
  Status s =
      parse(npy_with_dict("{'shape': (2, 3), 'fortran_order': False, 'descr': '<f4'}", 24), a);
  ASSERT_TRUE(s) << s.message();
  EXPECT_EQ(a.ny, 2);
  EXPECT_EQ(a.nx, 3);
  std::string v2("\x93NUMPY\x02\x00", 8);
  std::string d = "{'descr': '<f4', 'fortran_order': False, 'shape': (1, 1), }\n";
  v2 += std::string{char(d.size()), 0, 0, 0} + d + std::string(4, '\0');
  ASSERT_TRUE(parse(v2, a));
  EXPECT_EQ(a.nx, 1);
}

TEST_F(NpyTest, RejectsEverythingElseWithOneLineNamingTheFile) {
  const std::string ok = "{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3), }";
  struct Case {
    std::string file;
    std::string expect;  // a fragment of the message
  };
  std::string v3 = npy_with_dict(ok, 24);
  v3[6] = 3;
  std::string no_newline = npy_with_dict(ok, 24);
  no_newline[10 + ok.size()] = ' ';
  const Case cases[] = {
      {"", "not a NumPy"},
      {"PK\x03\x04 this is a zip", "not a NumPy"},
      {v3, "version 3.0"},
      {no_newline, "newline"},
      {npy_with_dict("{'descr': '<f8', 'fortran_order': False, 'shape': (2, 3), }", 48), "'<f8'"},
      {npy_with_dict("{'descr': '>f4', 'fortran_order': False, 'shape': (2, 3), }", 24), "'>f4'"},
      {npy_with_dict("{'descr': '<f4', 'fortran_order': True, 'shape': (2, 3), }", 24), "Fortran"},
      {npy_with_dict("{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3, 1), }", 24),
       "3 dimensions"},
      {npy_with_dict("{'descr': '<f4', 'fortran_order': False, 'shape': (6,), }", 24),
       "1 dimensions"},
      {npy_with_dict("{'descr': '<f4', 'fortran_order': False, 'shape': (0, 3), }", 0),
       "out of range"},
      {npy_with_dict("{'descr': '<f4', 'fortran_order': False, 'shape': (-2, 3), }", 24),
       "non-integer"},
      {npy_with_dict("{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3), }", 20),
       "expected 24"},
      {npy_with_dict("{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3), }", 28),
       "expected 24"},
      {npy_with_dict("{'descr': '<f4', 'shape': (2, 3), }", 24), "missing key"},
      {npy_with_dict("{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3), 'x': 1}", 24),
       "'x'"},
      {npy_with_dict("{'descr': '<f4' 'fortran_order': False, 'shape': (2, 3)}", 24),
       "expected ','"},
      {npy_with_dict("{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3)} junk", 24),
       "after"},
      {npy_with_dict("{'descr': '<f4', 'fortran_order': False, 'shape': (99999999999, 3)}", 24),
       "out of range"},
      {npy_with_dict("{'descr': '<f4', 'fortran_order': False, 'shape': (1048577, 3)}", 24),
       "out of range"},
      {std::string("\x93NUMPY\x01\x00\xff\x00{", 11), "truncated"},
  };
  for (const Case& c : cases) {
    NpyArray a;
    Status s = parse(c.file, a);
    ASSERT_FALSE(s) << "accepted: " << c.expect;
    EXPECT_EQ(s.message().rfind("x.npy: ", 0), 0u) << s.message();
    EXPECT_NE(s.message().find(c.expect), std::string::npos) << s.message();
    EXPECT_EQ(s.message().find('\n'), std::string::npos) << s.message();
  }
}

TEST_F(NpyTest, MissingFileAndDirectoryAreReported) {
  NpyArray a;
  Status s = read_npy(dir_ / "nope.npy", a);
  ASSERT_FALSE(s);
  EXPECT_NE(s.message().find("not found"), std::string::npos);
  s = read_npy(dir_, a);
  ASSERT_FALSE(s);
  EXPECT_NE(s.message().find("is a folder"), std::string::npos);
}

TEST_F(NpyTest, WriteIntoAMissingFolderFailsAndLeavesNothing) {
  FieldF f({2, 2}, 1);
  Status s = write_npy(dir_ / "missing" / "u.npy", f.view(f.interior()));
  ASSERT_FALSE(s);
  EXPECT_NE(s.message().find("cannot create"), std::string::npos) << s.message();
  EXPECT_EQ(file_count(), 0u);
}

// NumPy (a test helper only) reads what we write and we read what it writes.
TEST_F(NpyTest, NumPyCrossCheck) {
  if (std::system("/usr/bin/python3 -c 'import numpy' >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "python3-numpy is not installed";
  FieldF f({5, 3}, 1);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 5; ++x) f(x, y) = float(10 * y + x) + 0.25f;
  ASSERT_TRUE(write_npy(dir_ / "ours.npy", f.view(f.interior())));
  const std::string script =
      "import numpy as np, sys\n"
      "d = sys.argv[1]\n"
      "a = np.load(d + '/ours.npy')\n"
      "assert a.dtype == np.dtype('<f4') and a.shape == (3, 5) and a.flags.c_contiguous\n"
      "assert (a == np.arange(3)[:, None] * 10 + np.arange(5)[None, :] + 0.25).all()\n"
      "np.save(d + '/theirs.npy', (np.arange(12, dtype='<f4').reshape(4, 3) * -1.5))\n";
  std::ofstream(dir_ / "check.py") << script;
  ASSERT_EQ(std::system(
                ("/usr/bin/python3 " + (dir_ / "check.py").string() + " " + dir_.string()).c_str()),
            0);
  NpyArray a;
  Status s = read_npy(dir_ / "theirs.npy", a);
  ASSERT_TRUE(s) << s.message();
  ASSERT_EQ(a.ny, 4);
  ASSERT_EQ(a.nx, 3);
  for (int i = 0; i < 12; ++i) EXPECT_EQ(a.data[i], float(i) * -1.5f);
}

}  // namespace
}  // namespace ardcell
