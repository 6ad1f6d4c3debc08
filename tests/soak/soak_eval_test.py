#!/usr/bin/env python3
"""Checks scripts/soak's log reading and goal evaluation on logs whose truth is known by construction.

Run: python3 tests/soak/soak_eval_test.py (standard library only; no hmp, no stress-ng needed).
"""
import json, os, sys, tempfile, unittest
from importlib.machinery import SourceFileLoader
from importlib.util import module_from_spec, spec_from_loader

SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts", "soak")


def load_soak():
    """scripts/soak has no .py extension, so it is loaded by path; its main() does not run on import."""
    sys.dont_write_bytecode = True  # no __pycache__ folder left beside the script
    loader = SourceFileLoader("soak", SCRIPT)
    module = module_from_spec(spec_from_loader("soak", loader))
    loader.exec_module(module)
    return module


soak = load_soak()


def note(song, key, late=0, tick=1000):
    return {"song": song, "track": 1, "key": key, "start_s": tick / 1000,
            "scheduled_tick": tick, "actual_tick": tick + late}


def counts(sent, played, late=0, stolen=0, rejected=0, skipped=0):
    return {"notes_sent": sent, "notes_played": played, "late": late, "stolen": stolen,
            "rejected": rejected, "skipped": skipped}


def clean_log(lates=(), rejected=0):
    """Two songs of 1000 notes each; note n of song 0 is late by lates[n] ticks."""
    lines, total_late = [], 0
    for song in range(2):
        for n in range(1000):
            late = lates[n] if song == 0 and n < len(lates) else 0
            total_late += late > 0
            lines.append(note(song, 60 + n % 12, late, 1000 + 100 * n))
        lines.append({"song_end": {"index": song, "path": f"s{song}.mid", "played_s": 100.0, **counts(1000, 1000)}})
    summary = counts(2000 + rejected, 2000, late=total_late, rejected=rejected)
    summary.update(songs_played=2, files_skipped=1, played_s=200.0, audio_underruns=0)
    return lines + [{"summary": summary}]


def flat_samples(minutes, kib_per_hour=0.0, base=50_000):
    """RSS and fd samples every 10 s; RSS grows linearly by kib_per_hour."""
    ts = range(0, int(minutes * 60) + 1, 10)
    return [[t, base + kib_per_hour * t / 3600] for t in ts], [[t, 14] for t in ts]


class SoakEvalTest(unittest.TestCase):
    def setUp(self):
        self.dir = tempfile.TemporaryDirectory()
        self.addCleanup(self.dir.cleanup)

    def judge(self, records, minutes=2, kib_per_hour=0.0, raw_lines=(), edit_samples=None, cpu_s=20.0):
        """The log written as hmp would, judged with flat (or steadily growing) samples; `edit_samples(rss,
        fds)` changes them first."""
        path = os.path.join(self.dir.name, "log.jsonl")
        with open(path, "w") as f:
            f.writelines(json.dumps(r) + "\n" for r in records)
            f.writelines(line + "\n" for line in raw_lines)
        rss, fds = flat_samples(minutes, kib_per_hour)
        if edit_samples:
            edit_samples(rss, fds)
        return soak.evaluate(soak.read_log(path), rss, fds, cpu_s=cpu_s, hmp_ok=True)

    def test_clean_log_passes(self):
        r = self.judge(clean_log())
        self.assertTrue(r["pass"], r["goals"])
        self.assertEqual(r["notes_started"], 2000)
        self.assertEqual(r["notes_lost"], 0)
        self.assertEqual(r["late_ticks"], {"0": 2000})
        self.assertEqual(r["songs_played"], 2)
        self.assertAlmostEqual(r["cpu_s_per_music_s"], 0.1)

    def test_one_note_two_ticks_late_fails_the_tick_goal_only(self):
        r = self.judge(clean_log(lates=[0, 0, 2]))
        self.assertFalse(r["goals"]["none_late_by_more_than_1_tick"])
        self.assertTrue(r["goals"]["late_at_most_0.1_percent"])  # 1 of 2000 = 0.05 %
        self.assertEqual(r["late_max_ticks"], 2)
        self.assertEqual(r["late_ticks"], {"0": 1999, "2": 1})
        self.assertFalse(r["pass"])

    def test_one_tick_late_is_allowed_but_counts(self):
        r = self.judge(clean_log(lates=[1]))
        self.assertTrue(r["goals"]["none_late_by_more_than_1_tick"])
        self.assertEqual(r["notes_late"], 1)
        self.assertTrue(r["pass"])

    def test_many_late_notes_fail_the_fraction_goal(self):
        r = self.judge(clean_log(lates=[1, 1, 1]))  # 3 of 2000 = 0.15 %
        self.assertFalse(r["goals"]["late_at_most_0.1_percent"])

    def test_a_rejected_note_fails(self):
        r = self.judge(clean_log(rejected=1))  # sent but never started: lost too
        self.assertFalse(r["goals"]["no_notes_lost_or_rejected"])
        self.assertFalse(r["pass"])

    def test_a_rejection_fails_even_when_nothing_is_lost(self):
        records = clean_log()
        records[-1]["summary"]["rejected"] = 1  # e.g. a report refused, then sent again and played
        r = self.judge(records)
        self.assertEqual(r["notes_lost"], 0)
        self.assertFalse(r["goals"]["no_notes_lost_or_rejected"])

    def test_a_lost_note_fails(self):
        records = clean_log()
        records[-1]["summary"]["notes_sent"] += 1
        r = self.judge(records)
        self.assertEqual(r["notes_lost"], 1)
        self.assertFalse(r["goals"]["no_notes_lost_or_rejected"])

    def test_a_note_never_sent_after_a_stall_is_lost(self):
        records = clean_log()
        records[-1]["summary"]["skipped"] = 2  # stale after a stall: never sent, never felt
        r = self.judge(records)
        self.assertEqual(r["notes_lost"], 2)
        self.assertFalse(r["goals"]["no_notes_lost_or_rejected"])

    def test_notes_cancelled_at_the_stop_are_not_lost(self):
        # Sent ahead of the SIGINT and dropped by the stop: the player counts them, the soak does not.
        records = clean_log()
        records[-1]["summary"]["notes_sent"] += 2
        records[-1]["summary"]["cancelled"] = 2
        r = self.judge(records)
        self.assertEqual((r["notes_lost"], r["notes_cancelled"]), (0, 2))
        self.assertTrue(r["goals"]["no_notes_lost_or_rejected"])
        records[-1]["summary"]["cancelled"] = 1  # one of the two was due and did not start: lost
        self.assertEqual(self.judge(records)["notes_lost"], 1)

    def test_negative_lost_is_clamped_and_flagged(self):
        records = clean_log()
        records[-1]["summary"]["notes_sent"] -= 5
        r = self.judge(records)
        self.assertEqual(r["notes_lost"], 0)
        self.assertTrue(r["notes_lost_negative"])

    def test_rss_growing_2_mib_per_hour_over_20_minutes_fails(self):
        r = self.judge(clean_log(), minutes=20, kib_per_hour=2048)
        self.assertAlmostEqual(r["rss_growth_kib_per_hour"], 2048, delta=1)
        self.assertEqual(r["rss_fit_from_s"], 60)
        self.assertFalse(r["goals"]["rss_growth_at_most_1_mib_per_hour"])
        self.assertFalse(r["pass"])

    def test_rss_growing_half_a_mib_per_hour_over_20_minutes_passes(self):
        r = self.judge(clean_log(), minutes=20, kib_per_hour=512)
        self.assertTrue(r["goals"]["rss_growth_at_most_1_mib_per_hour"])
        self.assertTrue(r["pass"])

    def test_rss_warm_up_is_left_out_of_the_fit(self):
        def warm_up(rss, _fds):
            rss[0][1] -= 30_000  # loading the first song: a jump before 60 s, not a leak
        r = self.judge(clean_log(), minutes=20, edit_samples=warm_up, cpu_s=1.0)
        self.assertAlmostEqual(r["rss_growth_kib_per_hour"], 0, delta=1)

    def test_growth_counts_from_the_end_of_the_first_song(self):
        records = clean_log()
        records[1000]["song_end"]["wall_s"] = 300.0  # the first song ended 5 minutes in

        def load_then_grow(rss, _fds):
            for p in rss:
                p[1] += 4096 if p[0] >= 200 else 0   # the first song loading: before its end, not counted
                p[1] += 2048 if p[0] >= 900 else 0   # a step after it: counted
        r = self.judge(records, minutes=30, edit_samples=load_then_grow)
        self.assertEqual(r["rss_fit_from_s"], 300.0)
        self.assertAlmostEqual(r["rss_growth_kib_per_hour"], 2048 / (1500 / 3600), delta=1)
        self.assertFalse(r["goals"]["rss_growth_at_most_1_mib_per_hour"])

    def between_songs_log(self, song_end_s, points):
        """clean_log with the first song ending at song_end_s and between_songs lines [(wall_s, kib)...]
        after it (and one before the first song, far lower: hmp before it loaded anything)."""
        records = clean_log()
        records[1000]["song_end"]["wall_s"] = song_end_s
        lines = [{"between_songs": {"wall_s": 0.0, "rss_kib": 1000}}]
        lines += [{"between_songs": {"wall_s": t, "rss_kib": kib}} for t, kib in points]
        return lines + records

    def test_growth_between_songs_ignores_the_song_playing(self):
        # The samples climb 8 MiB while a big song plays and stay there; between songs (its memory handed
        # back) the RSS is flat: no leak, and the samples' step must not count.
        points = [(t, 50_000) for t in range(120, 1800, 120)]

        def big_song(rss, _fds):
            for p in rss:
                p[1] += 8192 if p[0] >= 600 else 0
        r = self.judge(self.between_songs_log(110.0, points), minutes=30, edit_samples=big_song)
        self.assertEqual(r["rss_growth_from"], "between_songs")
        self.assertEqual(r["rss_fit_from_s"], 120)
        self.assertAlmostEqual(r["rss_growth_kib_per_hour"], 0, delta=1e-9)
        self.assertTrue(r["goals"]["rss_growth_at_most_1_mib_per_hour"])

    def test_growth_between_songs_of_2_mib_per_hour_fails(self):
        points = [(t, 50_000 + 2048 * t / 3600) for t in range(120, 1800, 120)]
        r = self.judge(self.between_songs_log(110.0, points), minutes=30)
        self.assertEqual(r["rss_growth_from"], "between_songs")
        self.assertAlmostEqual(r["rss_growth_kib_per_hour"], 2048, delta=1)
        self.assertAlmostEqual(r["rss_slope_kib_per_hour"], 2048, delta=1)
        self.assertFalse(r["goals"]["rss_growth_at_most_1_mib_per_hour"])

    def test_too_few_points_between_songs_fall_back_to_the_samples(self):
        # Two points 100 s apart cannot tell 1 MiB/h: the samples (growing 2 MiB/h) judge instead.
        r = self.judge(self.between_songs_log(110.0, [(120, 50_000), (220, 50_000)]), minutes=30,
                       kib_per_hour=2048)
        self.assertEqual(r["rss_growth_from"], "samples")
        self.assertFalse(r["goals"]["rss_growth_at_most_1_mib_per_hour"])

    def test_two_minute_run_leaves_the_rss_goal_unjudged(self):
        r = self.judge(clean_log(), minutes=2, kib_per_hour=100_000)
        self.assertIsNone(r["goals"]["rss_growth_at_most_1_mib_per_hour"])
        self.assertEqual(r["rss_fit_from_s"], 30)  # a quarter of 120 s is earlier than 60 s
        self.assertTrue(r["pass"])

    def test_fds_growing_fails(self):
        def leak(_rss, fds):
            fds[-1][1] += 3
        r = self.judge(clean_log(), edit_samples=leak, cpu_s=1.0)
        self.assertFalse(r["goals"]["fds_flat"])

    def test_an_underrun_fails(self):
        records = clean_log()
        records[-1]["summary"]["audio_underruns"] = 1
        self.assertFalse(self.judge(records)["goals"]["no_underrun"])

    def test_a_bad_hmp_ending_fails_even_with_good_figures(self):
        path = os.path.join(self.dir.name, "log.jsonl")
        with open(path, "w") as f:
            f.writelines(json.dumps(r) + "\n" for r in clean_log())
        rss, fds = flat_samples(2)
        self.assertFalse(soak.evaluate(soak.read_log(path), rss, fds, cpu_s=1.0, hmp_ok=False)["pass"])

    def test_a_load_that_ignores_sigterm_is_killed_and_remarked_not_failed(self):
        """A stand-in hmp that ends with 130 on SIGINT and a stand-in load that ignores SIGTERM: the load is
        killed after the grace, which is a remark, and hmp's run has no problem."""
        hmp = ["sh", "-c", "trap 'exit 130' INT; while :; do sleep 0.05; done"]
        load = ["sh", "-c", "trap '' TERM; while :; do sleep 0.05; done"]
        grace, soak.LOAD_GRACE_S = soak.LOAD_GRACE_S, 1
        self.addCleanup(setattr, soak, "LOAD_GRACE_S", grace)
        log, err = os.path.join(self.dir.name, "log.jsonl"), os.path.join(self.dir.name, "err.txt")
        code, _, _, _, problems, remarks = soak.run(hmp, load, 1.5, log, err)
        self.assertEqual((code, problems), (130, []))
        self.assertEqual(remarks, ["the load did not end within 1 s of SIGTERM: killed"])

    def test_missing_keys_do_not_crash(self):
        records = [{"track": 1, "key": 60, "start_s": 0.5, "scheduled_tick": 10, "actual_tick": 11},  # no "song"
                   {"track": 1, "key": 61},  # no ticks at all
                   {"song_end": {}},
                   {"summary": {"notes_sent": 3}}]
        r = self.judge(records, raw_lines=["not json", "[1, 2]", ""])
        self.assertIsNone(r["notes_started"])
        self.assertIsNone(r["notes_lost"])
        self.assertIsNone(r["late_fraction"])
        self.assertIsNone(r["audio_underruns"])
        self.assertEqual((r["music_s"], r["music_s_from"]), (0.5, "notes"))  # no played_s: the notes' song time
        self.assertEqual(r["late_max_ticks"], 1)
        self.assertIsNone(r["goals"]["no_underrun"])
        self.assertIsNone(r["goals"]["no_notes_lost_or_rejected"])
        self.assertEqual(r["log_bad_lines"], 2)
        json.dumps(r)  # still a valid summary

    def test_old_one_song_log_without_playlist_keys(self):
        records = [note(0, 60), note(0, 62)]
        for rec in records:
            del rec["song"]
        records.append({"summary": {"notes_sent": 2, "notes_played": 2, "late": 0, "stolen": 0, "rejected": 0}})
        r = self.judge(records)
        self.assertIsNone(r["songs_played"])
        self.assertIsNone(r["goals"]["no_underrun"])
        self.assertTrue(r["goals"]["no_notes_lost_or_rejected"])
        self.assertTrue(r["pass"])

    def test_no_log_at_all(self):
        rss, fds = flat_samples(2)
        r = soak.evaluate(soak.read_log(os.path.join(self.dir.name, "missing.jsonl")), rss, fds, None, hmp_ok=True)
        self.assertFalse(r["log_found"])
        self.assertFalse(r["pass"])  # nothing measured cannot pass


if __name__ == "__main__":
    unittest.main()
