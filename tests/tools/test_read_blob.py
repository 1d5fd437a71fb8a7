#!/usr/bin/env python3
"""Tests tools/read_blob.py on a blob written by the C++ writer.

usage: test_read_blob.py PATH_TO_test_blob_EXECUTABLE
The C++ test BlobSample.WriteForPythonReader (tests/core/test_blob.cpp) writes the
sample blob; the values checked here are the ones it puts in.
"""
import os
import re
import subprocess
import sys
import tempfile
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, "tools"))

import numpy as np  # noqa: E402

import read_blob  # noqa: E402
from writer_arg import pop_writer  # noqa: E402

WRITER = None


class ReadBlobTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.path = os.path.join(cls.tmp.name, "sample.blob")
        env = dict(os.environ, NNS_BLOB_SAMPLE_OUT=cls.path)
        subprocess.run([WRITER, "--gtest_filter=BlobSample.WriteForPythonReader"], env=env,
                       check=True, stdout=subprocess.DEVNULL)
        with open(cls.path, "rb") as f:
            cls.bytes = f.read()

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def write(self, name, data):
        p = os.path.join(self.tmp.name, name)
        with open(p, "wb") as f:
            f.write(data)
        return p

    def expect_error(self, data, what):
        p = self.write("bad.blob", data)
        with self.assertRaises(read_blob.BlobError) as cm:
            read_blob.load(p)
        self.assertIn(p, str(cm.exception))
        self.assertIn(what, str(cm.exception))

    def test_values_match_the_cpp_writer(self):
        kind, config, t = read_blob.load(self.path)
        self.assertEqual(kind, "test-model")
        self.assertEqual(config, {"activation": "prelu", "hidden": "16", "lr": "0.00020000000000000001"})
        self.assertEqual(float(config["lr"]), 2e-4)
        w = t["fc.weight"]
        self.assertEqual(w.dtype, np.float32)
        self.assertEqual(w.shape, (2, 3))
        np.testing.assert_array_equal(w, np.array([[1, -2, 3.5], [0, 1e-30, -0.0]], dtype=np.float32))
        self.assertTrue(np.signbit(w[1, 2]))
        np.testing.assert_array_equal(t["fc.bias"], np.array([0.1, -0.2, 1e300]))
        self.assertEqual(t["fc.bias"].dtype, np.float64)
        self.assertEqual(t["rng"].dtype, np.uint64)
        self.assertEqual(t["rng"].tolist(), [1, 2**64 - 1, 42, 7])
        self.assertEqual(t["step"].tolist(), [-3])
        self.assertEqual(t["empty"].shape, (0, 5))
        self.assertEqual(t["scalar"].shape, ())
        self.assertEqual(float(t["scalar"]), 2.5)
        self.assertEqual(list(t), ["fc.weight", "fc.bias", "rng", "step", "empty", "scalar"])

    def test_tensor_data_is_64_byte_aligned(self):
        i = self.bytes.find(np.array([0.1, -0.2, 1e300]).tobytes())
        self.assertGreater(i, 0)
        self.assertEqual(i % 64, 0)

    def test_summary_lists_every_tensor(self):
        s = read_blob.summary(self.path)
        self.assertIn("kind 'test-model'", s)
        self.assertIn("fc.weight", s)
        self.assertIn("f32 [2,3]", s)
        self.assertIn("u64 [4]", s)

    def test_command_line(self):
        r = subprocess.run([sys.executable, os.path.join(ROOT, "tools", "read_blob.py"), self.path],
                           capture_output=True, text=True)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("6 tensors", r.stdout)
        bad = self.write("cli-bad.blob", b"junk")
        r = subprocess.run([sys.executable, os.path.join(ROOT, "tools", "read_blob.py"), bad],
                           capture_output=True, text=True)
        self.assertEqual(r.returncode, 1)
        self.assertIn("bad magic", r.stderr)

    def test_truncated(self):
        for n in (0, 5, 20, 40, len(self.bytes) // 2, len(self.bytes) - 1):
            with self.subTest(n=n):
                self.expect_error(self.bytes[:n], "truncated")

    def test_corrupt(self):
        for at in (30, len(self.bytes) // 2, len(self.bytes) - 1):
            with self.subTest(at=at):
                bad = bytearray(self.bytes)
                bad[at] ^= 0x10
                self.expect_error(bytes(bad), "checksum mismatch")

    def test_wrong_magic_and_version(self):
        self.expect_error(b"X" + self.bytes[1:], "bad magic")
        bad = bytearray(self.bytes)
        bad[8] = 2
        self.expect_error(bytes(bad), "format version 2 is not supported")

    def test_trailing_bytes(self):
        self.expect_error(self.bytes + b"junk", "unexpected bytes")

    def test_example_in_the_format_document(self):
        # The hex dump in docs/weights-format.md must be a valid blob with the stated content.
        with open(os.path.join(ROOT, "docs", "weights-format.md")) as f:
            doc = f.read()
        dump = doc[doc.index("## Example"):]
        data = bytearray()
        for line in re.findall(r"^[0-9a-f]{4}  (.{48})", dump, re.M):
            data += bytes.fromhex(line.replace(" ", ""))
        kind, config, t = read_blob.parse(bytes(data), "docs example")
        self.assertEqual((kind, config), ("demo", {"hidden": "2"}))
        np.testing.assert_array_equal(t["b"], np.array([1.0, 2.0], dtype=np.float32))


if __name__ == "__main__":
    WRITER = pop_writer(__doc__)
    unittest.main()
