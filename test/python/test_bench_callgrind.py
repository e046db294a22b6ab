"""preadaptive_mrac.bench.callgrind: counts from callgrind_annotate listings (shortened
listings of preadapt_sim) and the per-mode JSON file."""

import json
import os
import shutil
import tempfile
import unittest

import pkg_path  # noqa: F401
from preadaptive_mrac.bench import callgrind

INCLUSIVE = '''--------------------------------------------------------------------------------
116,483,962 (100.0%)  PROGRAM TOTALS
--------------------------------------------------------------------------------
Ir                   file:function
--------------------------------------------------------------------------------
113,635,771 (97.55%)  ???:main [/x/preadapt_sim]
104,908,356 (90.06%)  ???:preadaptive_mrac::ClosedLoop::run(SimOptions const&) [l.so]
 46,329,932 (39.77%)  ???:preadaptive_mrac::Controller::step(StepInput const&) [l.so]
 31,641,216 (27.16%)  ???:preadaptive_mrac::Plant::step(double, Vec const&, double, double)
 31,080,000 (26.68%)  ???:preadaptive_mrac::Plant::step3(double, Vec const&, double, double)
  1,000,000 ( 0.86%)  ???:preadaptive_mrac::Controller::step(StepInput const&)'2 [l.so]
'''

EXCLUSIVE = '''--------------------------------------------------------------------------------
Ir                   file:function
--------------------------------------------------------------------------------
 6,295,165 ( 2.15%)  ???:Eigen::internal::general_matrix_vector_product<A>::run(long) [l.so]
   100,000 ( 0.01%)  ???:Eigen::internal::general_matrix_vector_product<B>::run(long) [l.so]
 5,059,038 ( 1.72%)  ???:preadaptive_mrac::ClosedLoop::run(SimOptions const&) [l.so]
'''


class TestCallgrind(unittest.TestCase):
    def test_inclusive_counts_take_the_first_match(self):
        c = callgrind.inclusive_counts(INCLUSIVE)
        self.assertEqual(c['total'], 116483962)
        self.assertEqual(c['closed_loop_run'], 104908356)
        self.assertEqual(c['controller_step'], 46329932)  # not the recursive '2 line
        self.assertEqual(c['plant_step'], 31641216)  # Plant::step(, not Plant::step3(
        self.assertNotIn('sensitivity_accumulate', c)

    def test_gemv_sums_every_instantiation(self):
        self.assertEqual(callgrind.gemv_instructions(EXCLUSIVE), 6395165)

    def test_record_keeps_other_modes(self):
        d = tempfile.mkdtemp(prefix='pmrac_cg_')
        try:
            out = os.path.join(d, 'callgrind.json')
            callgrind.record(out, 'rac', INCLUSIVE, EXCLUSIVE)
            callgrind.record(out, 'pa', INCLUSIVE)
            with open(out) as f:
                data = json.load(f)
            self.assertEqual(set(data), {'rac', 'pa'})
            self.assertEqual(data['rac']['eigen_gemv'], 6395165)
            self.assertNotIn('eigen_gemv', data['pa'])
        finally:
            shutil.rmtree(d)


if __name__ == '__main__':
    unittest.main()
