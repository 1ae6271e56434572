//! Correctness of every available backend against a naive f64 DFT and rustfft (oracle only),
//! batch determinism, and the real-output property.

use super::backend::{backend_of_code, forced_code, NOT_FORCED};
use super::*;
use rustfft::num_complex::Complex;

/// SplitMix64: a tiny deterministic PRNG so tests need no `rand`.
struct Rng(u64);

impl Rng {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [-1, 1).
    fn next_f32(&mut self) -> f32 {
        ((self.next_u64() >> 40) as f32 / (1u64 << 24) as f32) * 2.0 - 1.0
    }
}

fn sizes() -> impl Iterator<Item = GridSize> {
    (4..=10).map(|l| GridSize::new(1 << l).unwrap())
}

fn random_field(size: GridSize, seed: u64) -> SplitField {
    let mut rng = Rng(seed);
    let mut f = SplitField::zeros(size);
    let (re, im) = f.planes_mut();
    for (r, i) in re.iter_mut().zip(im.iter_mut()) {
        *r = rng.next_f32();
        *i = rng.next_f32();
    }
    f
}

fn to_complex64(f: &SplitField) -> Vec<Complex<f64>> {
    f.re.iter()
        .zip(f.im.iter())
        .map(|(&r, &i)| Complex::new(r as f64, i as f64))
        .collect()
}

/// Relative RMS error of `got` against `want`.
fn rel_rms(got: &SplitField, want: &[Complex<f64>]) -> f64 {
    let (mut err, mut norm) = (0.0, 0.0);
    for ((&r, &i), w) in got.re.iter().zip(got.im.iter()).zip(want) {
        err += (Complex::new(r as f64, i as f64) - w).norm_sqr();
        norm += w.norm_sqr();
    }
    (err / norm).sqrt()
}

/// Naive inverse 2D DFT in f64: an O(N²) DFT of every row, then of every column.
fn naive_inverse_2d(x: &[Complex<f64>], n: usize) -> Vec<Complex<f64>> {
    let w: Vec<Complex<f64>> = (0..n)
        .map(|k| Complex::from_polar(1.0, 2.0 * std::f64::consts::PI * k as f64 / n as f64))
        .collect();
    let dft = |input: &[Complex<f64>], out: &mut [Complex<f64>]| {
        for (k, o) in out.iter_mut().enumerate() {
            *o = input
                .iter()
                .enumerate()
                .map(|(j, &v)| v * w[(j * k) % n])
                .sum();
        }
    };
    let mut rows = vec![Complex::default(); n * n];
    for (src, dst) in x.chunks_exact(n).zip(rows.chunks_exact_mut(n)) {
        dft(src, dst);
    }
    let mut out = vec![Complex::default(); n * n];
    let mut col = vec![Complex::default(); n];
    let mut res = vec![Complex::default(); n];
    for c in 0..n {
        for r in 0..n {
            col[r] = rows[r * n + c];
        }
        dft(&col, &mut res);
        for r in 0..n {
            out[r * n + c] = res[r];
        }
    }
    out
}

/// rustfft (f64) inverse 2D: rows, then columns.
fn rustfft_inverse_2d(x: &[Complex<f64>], n: usize) -> Vec<Complex<f64>> {
    let fft = rustfft::FftPlanner::<f64>::new().plan_fft_inverse(n);
    let mut a = x.to_vec();
    fft.process(&mut a);
    let mut t = vec![Complex::default(); n * n];
    for r in 0..n {
        for c in 0..n {
            t[c * n + r] = a[r * n + c];
        }
    }
    fft.process(&mut t);
    for r in 0..n {
        for c in 0..n {
            a[r * n + c] = t[c * n + r];
        }
    }
    a
}

fn run_inverse(fft: &Fft2d, input: &SplitField) -> SplitField {
    let mut f = input.clone();
    let mut s = SplitField::zeros(input.size());
    fft.inverse(&mut f, &mut s);
    f
}

#[test]
fn all_backends_match_naive_dft() {
    for backend in Backend::available() {
        for size in sizes().filter(|s| s.n() <= 128) {
            let input = random_field(size, 1 + size.n() as u64);
            let want = naive_inverse_2d(&to_complex64(&input), size.n());
            let fft = Fft2d::with_backend(size, backend).unwrap();
            let err = rel_rms(&run_inverse(&fft, &input), &want);
            assert!(
                err < 1e-5,
                "{backend} N={size}: rel RMS {err:e} vs naive DFT"
            );
        }
    }
}

#[test]
fn all_backends_match_rustfft() {
    for size in sizes() {
        let input = random_field(size, 100 + size.n() as u64);
        let want = rustfft_inverse_2d(&to_complex64(&input), size.n());
        for backend in Backend::available() {
            let fft = Fft2d::with_backend(size, backend).unwrap();
            assert_eq!(fft.backend(), backend);
            assert_eq!(fft.size(), size);
            let err = rel_rms(&run_inverse(&fft, &input), &want);
            assert!(err < 1e-5, "{backend} N={size}: rel RMS {err:e} vs rustfft");
        }
    }
}

#[test]
fn single_impulses_give_plane_waves() {
    // A lone coefficient at (kr, kc) must give exp(+2πi(kr·r + kc·c)/N): catches sign and
    // transpose mistakes independently of any oracle.
    let size = GridSize::new(32).unwrap();
    let n = size.n();
    for backend in Backend::available() {
        let fft = Fft2d::with_backend(size, backend).unwrap();
        for (kr, kc) in [(0, 0), (1, 0), (0, 1), (3, 5), (31, 17)] {
            let mut input = SplitField::zeros(size);
            input.re[kr * n + kc] = 1.0;
            let out = run_inverse(&fft, &input);
            for r in 0..n {
                for c in 0..n {
                    let ph = 2.0 * std::f64::consts::PI * ((kr * r + kc * c) % n) as f64 / n as f64;
                    let (re, im) = (out.re[r * n + c] as f64, out.im[r * n + c] as f64);
                    assert!(
                        (re - ph.cos()).abs() < 1e-5 && (im - ph.sin()).abs() < 1e-5,
                        "{backend} ({kr},{kc}) at ({r},{c}): {re} {im}"
                    );
                }
            }
        }
    }
}

fn bits(fields: &[SplitField]) -> Vec<u32> {
    fields
        .iter()
        .flat_map(|f| f.re.iter().chain(f.im.iter()).map(|x| x.to_bits()))
        .collect()
}

#[test]
fn batch_is_bit_identical_to_single_for_any_thread_count() {
    for backend in Backend::available() {
        for size in [16, 128, 256].map(|n| GridSize::new(n).unwrap()) {
            let fft = Fft2d::with_backend(size, backend).unwrap();
            // Four fields (the ocean's batch) and one (forces splitting a field across tasks).
            for count in [4, 1] {
                let inputs: Vec<SplitField> =
                    (0..count).map(|i| random_field(size, 7 + i)).collect();
                let single: Vec<SplitField> = inputs.iter().map(|f| run_inverse(&fft, f)).collect();
                let want = bits(&single);
                for threads in [1, 2, 4] {
                    let pool = rayon::ThreadPoolBuilder::new()
                        .num_threads(threads)
                        .build()
                        .unwrap();
                    // One scratch per field, and fewer (fields transformed in groups).
                    for scratches in (1..=count).rev() {
                        let mut fields = inputs.clone();
                        let mut scratch: Vec<SplitField> =
                            (0..scratches).map(|_| SplitField::zeros(size)).collect();
                        pool.install(|| fft.inverse_batch(&mut fields, &mut scratch));
                        assert!(
                            bits(&fields) == want,
                            "{backend} N={size}: batch of {count} with {scratches} scratch on \
                             {threads} threads differs from single"
                        );
                    }
                }
            }
        }
    }
}

/// `f` with zeros outside `support`, and the same with NaN there: what lies outside the
/// support (and the scratch) holds NaN in a sparse transform, so none of it may reach the
/// result.
fn masked(f: SplitField, support: &Support) -> (SplitField, SplitField) {
    let n = f.size().n();
    let (mut zeros, mut nans) = (f.clone(), f);
    let outside = |t: &usize| !(support.rows.contains(&(t / n)) && support.cols.contains(&(t % n)));
    for t in (0..n * n).filter(outside) {
        (zeros.re[t], zeros.im[t]) = (0.0, 0.0);
        (nans.re[t], nans.im[t]) = (f32::NAN, f32::NAN);
    }
    (zeros, nans)
}

#[test]
fn sparse_batch_equals_the_full_one_and_reads_only_the_support() {
    for backend in Backend::available() {
        for size in [16, 128, 256].map(|n| GridSize::new(n).unwrap()) {
            let n = size.n();
            let fft = Fft2d::with_backend(size, backend).unwrap();
            // Inside one strip, across strips, a single row, nothing, everything.
            let centre = n / 2 - n / 6..n / 2 + n / 6 + 1;
            let supports = [
                Support {
                    rows: 2..n - 3,
                    cols: 3..9,
                },
                Support {
                    rows: centre.clone(),
                    cols: centre,
                },
                Support {
                    rows: 5..6,
                    cols: 0..n,
                },
                Support {
                    rows: 0..0,
                    cols: 0..0,
                },
                Support::full(size),
            ];
            for (k, support) in supports.into_iter().enumerate() {
                let (input, sparse) = masked(random_field(size, 91 + k as u64), &support);
                let mut want = [input.clone(), input.clone()];
                fft.inverse_batch(&mut want, &mut [SplitField::zeros(size)]);
                for threads in [1, 2] {
                    let pool = rayon::ThreadPoolBuilder::new()
                        .num_threads(threads)
                        .build()
                        .unwrap();
                    let mut got = [sparse.clone(), sparse.clone()];
                    let mut scratch = [SplitField::zeros(size), SplitField::zeros(size)];
                    for s in &mut scratch {
                        s.re.fill(f32::NAN);
                        s.im.fill(f32::NAN);
                    }
                    let scratch = &mut scratch[..threads];
                    pool.install(|| fft.inverse_batch_support(&mut got, scratch, &support));
                    for (g, w) in got.iter().zip(&want) {
                        // Equal as numbers: zeros read as zeros may differ in sign from computed ones.
                        assert!(
                            g.re.iter().zip(w.re.iter()).all(|(a, b)| a == b)
                                && g.im.iter().zip(w.im.iter()).all(|(a, b)| a == b),
                            "{backend} N={n} {support:?} on {threads} threads differs"
                        );
                    }
                }
            }
        }
    }
}

/// A random Hermitian spectrum: X[k] = (Y[k] + conj(Y[−k])) / 2.
fn hermitian(size: GridSize, seed: u64) -> SplitField {
    let n = size.n();
    let y = random_field(size, seed);
    let mut x = SplitField::zeros(size);
    for r in 0..n {
        for c in 0..n {
            let (i, j) = (r * n + c, ((n - r) % n) * n + (n - c) % n);
            x.re[i] = 0.5 * (y.re[i] + y.re[j]);
            x.im[i] = 0.5 * (y.im[i] - y.im[j]);
        }
    }
    x
}

/// `f` transformed alone as `output` with `support`, on the current pool, one scratch field
/// filled with NaN (none of it may reach the result).
fn transform_as(fft: &Fft2d, f: &SplitField, output: Output, support: &Support) -> SplitField {
    let mut fields = [f.clone()];
    let mut scratch = [SplitField::zeros(f.size())];
    scratch[0].re.fill(f32::NAN);
    scratch[0].im.fill(f32::NAN);
    fft.inverse_batch_support_as(&mut fields, &[output], &mut scratch, support);
    let [out] = fields;
    out
}

/// The rows 0..N/2 that [`Output::RealRowPairs`] defines, both planes.
fn paired_rows(f: &SplitField) -> Vec<u32> {
    let half = f.size().texels() / 2;
    f.re[..half]
        .iter()
        .chain(&f.im[..half])
        .map(|x| x.to_bits())
        .collect()
}

#[test]
fn real_row_pairs_are_the_real_transform_by_row_pairs() {
    for backend in Backend::available() {
        for size in sizes() {
            let n = size.n();
            let x = hermitian(size, 300 + n as u64);
            let fft = Fft2d::with_backend(size, backend).unwrap();
            let want = run_inverse(&fft, &x);
            let got = transform_as(&fft, &x, Output::RealRowPairs, &Support::full(size));
            let (mut err, mut norm) = (0.0f64, 0.0f64);
            for p in 0..n / 2 {
                for c in 0..n {
                    let (even, odd) = (want.re[2 * p * n + c], want.re[(2 * p + 1) * n + c]);
                    let (re, im) = (got.re[p * n + c], got.im[p * n + c]);
                    err += ((re - even) as f64).powi(2) + ((im - odd) as f64).powi(2);
                    norm += (even as f64).powi(2) + (odd as f64).powi(2);
                }
            }
            let rel = (err / norm).sqrt();
            assert!(
                rel < 1e-5,
                "{backend} N={n}: rel RMS {rel:e} against the complex transform"
            );
        }
    }
}

#[test]
fn real_row_pairs_read_only_the_support_and_ignore_threads() {
    for backend in Backend::available() {
        for size in [16, 64, 256].map(|n| GridSize::new(n).unwrap()) {
            let n = size.n();
            let fft = Fft2d::with_backend(size, backend).unwrap();
            // Centred rows fold into two runs (N/2 − a.. and ..b); one half only; one row.
            let centre = n / 2 - n / 6..n / 2 + n / 6 + 1;
            let supports = [
                Support {
                    rows: centre.clone(),
                    cols: centre,
                },
                Support {
                    rows: n / 2 + 1..n,
                    cols: 3..n - 2,
                },
                Support {
                    rows: 5..6,
                    cols: 0..n,
                },
                Support::full(size),
            ];
            for (k, support) in supports.into_iter().enumerate() {
                let (input, sparse) = masked(hermitian(size, 400 + k as u64), &support);
                let whole = transform_as(&fft, &input, Output::RealRowPairs, &Support::full(size));
                let got = transform_as(&fft, &sparse, Output::RealRowPairs, &support);
                let half = n * n / 2;
                // Equal as numbers: zeros read as zeros may differ in sign from computed ones.
                assert!(
                    got.re[..half]
                        .iter()
                        .zip(&whole.re[..half])
                        .all(|(a, b)| a == b)
                        && got.im[..half]
                            .iter()
                            .zip(&whole.im[..half])
                            .all(|(a, b)| a == b),
                    "{backend} N={n} {support:?}: the sparse fold differs"
                );
                // A batch mixing both outputs, in groups, on any thread count: the same bits.
                let full = transform_as(&fft, &sparse, Output::Complex, &support);
                for threads in [1, 2, 4] {
                    let pool = rayon::ThreadPoolBuilder::new()
                        .num_threads(threads)
                        .build()
                        .unwrap();
                    for scratches in [1, 2] {
                        let mut fields = [sparse.clone(), sparse.clone()];
                        let mut scratch: Vec<SplitField> =
                            (0..scratches).map(|_| SplitField::zeros(size)).collect();
                        let outputs = [Output::Complex, Output::RealRowPairs];
                        pool.install(|| {
                            fft.inverse_batch_support_as(
                                &mut fields,
                                &outputs,
                                &mut scratch,
                                &support,
                            )
                        });
                        assert!(
                            bits(&fields[..1]) == bits(std::slice::from_ref(&full))
                                && paired_rows(&fields[1]) == paired_rows(&got),
                            "{backend} N={n} {support:?}: {threads} threads, {scratches} scratch"
                        );
                    }
                }
            }
        }
    }
}

#[test]
fn hermitian_input_gives_real_output() {
    for backend in Backend::available() {
        for size in sizes() {
            let n = size.n();
            let x = hermitian(size, 55 + n as u64);
            let fft = Fft2d::with_backend(size, backend).unwrap();
            let out = run_inverse(&fft, &x);
            let rms = |v: &[f32]| {
                (v.iter().map(|&a| (a as f64).powi(2)).sum::<f64>() / v.len() as f64).sqrt()
            };
            let ratio = rms(&out.im) / rms(&out.re);
            assert!(
                ratio < 1e-6,
                "{backend} N={n}: imaginary residue {ratio:e} of RMS"
            );
        }
    }
}

#[test]
fn plans_are_shareable() {
    fn assert_send_sync<T: Send + Sync>() {}
    assert_send_sync::<Fft2d>();
}

#[test]
fn detect_and_availability_agree() {
    let avail = Backend::available();
    assert_eq!(avail[0], Backend::Scalar);
    #[cfg(target_arch = "x86_64")]
    assert!(avail.contains(&Backend::Sse2));
    #[cfg(target_arch = "aarch64")]
    assert!(avail.contains(&Backend::Neon));
    assert!(avail.contains(&Backend::detect()));
    let size = GridSize::new(16).unwrap();
    assert_eq!(Fft2d::new(size).backend(), Backend::detect());
    for b in [
        Backend::Scalar,
        Backend::Sse2,
        Backend::Avx2,
        Backend::Avx512,
        Backend::Neon,
    ] {
        assert_eq!(
            Fft2d::with_backend(size, b).is_some(),
            avail.contains(&b),
            "{b}"
        );
    }
}

#[test]
fn backend_names_round_trip() {
    for b in Backend::ALL {
        assert_eq!(Backend::from_name(&b.to_string()), Some(b));
        assert_eq!(Backend::from_name(&b.to_string().to_uppercase()), Some(b));
        assert_eq!(backend_of_code(forced_code(b)), Some(b));
    }
    assert_eq!(Backend::from_name("avx"), None);
    assert_eq!(backend_of_code(NOT_FORCED), None);
}

#[test]
fn forcing_a_backend_the_cpu_lacks_is_an_error_that_changes_nothing() {
    // Only the error path: forcing an available backend would change the plans of tests
    // running at the same time in this process.
    let before = forced_backend();
    for b in Backend::ALL.into_iter().filter(|b| !b.is_available()) {
        let err = force_backend(Some(b)).unwrap_err();
        assert_eq!(err.wanted, b);
        assert_eq!(err.available, Backend::available());
        let msg = err.to_string();
        assert!(
            msg.contains(&b.to_string()) && msg.contains("scalar"),
            "{msg}"
        );
        assert_eq!(forced_backend(), before);
    }
    #[cfg(target_arch = "x86_64")]
    assert!(force_backend(Some(Backend::Neon)).is_err());
    #[cfg(target_arch = "aarch64")]
    assert!(force_backend(Some(Backend::Avx2)).is_err());
}

#[test]
fn element_tiers_match_the_vector_width() {
    use crate::sim::simd::Tier;
    assert_eq!(Backend::Avx512.element_tier(), Tier::Avx512);
    assert_eq!(Backend::Avx2.element_tier(), Tier::Avx2);
    for b in [Backend::Scalar, Backend::Sse2, Backend::Neon] {
        assert_eq!(b.element_tier(), Tier::Baseline);
    }
}

#[test]
fn a_nested_working_buffer_comes_from_the_stack() {
    // The thread's buffer is in use by the outer call: the inner one must get another,
    // zeroed, and the thread's buffer must be usable again afterwards.
    let len = super::with_local(64, |outer| {
        outer[0].re[0] = 1.0;
        let at = outer.as_ptr();
        super::with_local(64, |inner| {
            assert_ne!(inner.as_ptr(), at);
            assert!(inner.iter().all(|r| r.re == [0.0; 16] && r.im == [0.0; 16]));
            inner.len()
        })
    });
    assert_eq!(len, 64);
    assert_eq!(super::with_local(32, |b| b.len()), 32);
}
