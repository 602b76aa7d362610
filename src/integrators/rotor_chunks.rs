//! Per-rotor passes across the rayon pool, shared by all integrators.
//!
//! The rotors are cut into chunks of [`ROTORS_PER_TASK`] consecutive rotors,
//! the same cuts for any number of threads, and each chunk is one rayon task.
//! A pass whose work on a rotor reads and writes only that rotor's entries
//! therefore gives results that do not depend on the number of threads.
//!
//! A pass works on anything that can be cut at a rotor index
//! ([`RotorChunk`]): slices, the scaled derivatives of a Nordsieck vector
//! (`gear::NordsieckChunk`), and tuples of these over the same rotors.

/// Rotors per rayon task (fewer cost more in scheduling than a second thread
/// saves).
pub const ROTORS_PER_TASK: usize = 256;

/// Per-rotor data that can be cut in two at a rotor index.
pub trait RotorChunk: Sized + Send {
    /// The number of rotors (for a tuple, of its shortest member, as `zip`).
    fn rotors(&self) -> usize;

    /// The rotors `..mid` and `mid..`, for `mid <= self.rotors()`.
    fn split_at_rotor(self, mid: usize) -> (Self, Self);
}

impl<T: Send> RotorChunk for &mut [T] {
    fn rotors(&self) -> usize {
        self.len()
    }

    fn split_at_rotor(self, mid: usize) -> (Self, Self) {
        self.split_at_mut(mid)
    }
}

impl<T: Sync> RotorChunk for &[T] {
    fn rotors(&self) -> usize {
        self.len()
    }

    fn split_at_rotor(self, mid: usize) -> (Self, Self) {
        self.split_at(mid)
    }
}

/// `RotorChunk` for tuples of chunks over the same rotors, cut together.
macro_rules! tuple_rotor_chunk {
    ($($member:ident $halves:ident $index:tt),+) => {
        impl<$($member: RotorChunk),+> RotorChunk for ($($member,)+) {
            fn rotors(&self) -> usize {
                usize::MAX$(.min(self.$index.rotors()))+
            }

            fn split_at_rotor(self, mid: usize) -> (Self, Self) {
                $(let $halves = self.$index.split_at_rotor(mid);)+
                (($($halves.0,)+), ($($halves.1,)+))
            }
        }
    };
}

tuple_rotor_chunk!(A a 0, B b 1);
tuple_rotor_chunk!(A a 0, B b 1, C c 2);
tuple_rotor_chunk!(A a 0, B b 1, C c 2, D d 3);
tuple_rotor_chunk!(A a 0, B b 1, C c 2, D d 3, E e 4);

/// Calls `pass` once per chunk of [`ROTORS_PER_TASK`] consecutive rotors of
/// `data` (the last chunk may be shorter; empty `data` is one empty chunk),
/// the chunks in parallel on the current rayon pool.
pub fn for_each_rotor_chunk<D: RotorChunk>(data: D, pass: impl Fn(D) + Sync) {
    split_into_tasks(data, &pass);
}

/// Halves `data` at a chunk boundary until one chunk is left, each half a
/// task of `rayon::join`.
fn split_into_tasks<D: RotorChunk>(data: D, pass: &(impl Fn(D) + Sync)) {
    let chunks = data.rotors().div_ceil(ROTORS_PER_TASK);
    if chunks <= 1 {
        pass(data);
        return;
    }
    let (left, right) = data.split_at_rotor(chunks / 2 * ROTORS_PER_TASK);
    let ((), ()) = rayon::join(
        || split_into_tasks(left, pass),
        || split_into_tasks(right, pass),
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Mutex;

    /// The chunks are the consecutive runs of `ROTORS_PER_TASK` rotors (the
    /// last one shorter), every member of a tuple cut at the same rotors, for
    /// 1 and 2 threads.
    #[test]
    fn chunks_are_fixed_runs_of_rotors_for_any_thread_count() {
        let n = 3 * ROTORS_PER_TASK + 17;
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .expect("a rayon pool");
            let mut index: Vec<usize> = vec![0; n];
            let label: Vec<usize> = (0..n).collect();
            let seen = Mutex::new(Vec::new());
            pool.install(|| {
                for_each_rotor_chunk((&mut index[..], &label[..]), |(out, labels)| {
                    out.copy_from_slice(labels);
                    let first = labels.first().copied();
                    seen.lock()
                        .expect("not poisoned")
                        .push((first, labels.len()));
                })
            });
            assert_eq!(index, label);
            let mut seen = seen.into_inner().expect("not poisoned");
            seen.sort();
            let expected: Vec<_> = (0..4)
                .map(|c| {
                    let start = c * ROTORS_PER_TASK;
                    (Some(start), ROTORS_PER_TASK.min(n - start))
                })
                .collect();
            assert_eq!(seen, expected, "{threads} threads");
        }
    }

    /// A tuple has as many rotors as its shortest member, and no rotors give
    /// one empty chunk.
    #[test]
    fn tuples_count_their_shortest_member_and_empty_data_is_one_chunk() {
        let (a, b) = (vec![0.0; 5], vec![0.0; 3]);
        assert_eq!((&a[..], &b[..]).rotors(), 3);
        let calls = Mutex::new(0);
        let empty: &[f64] = &[];
        for_each_rotor_chunk(empty, |chunk| {
            assert!(chunk.is_empty());
            *calls.lock().expect("not poisoned") += 1;
        });
        assert_eq!(calls.into_inner().expect("not poisoned"), 1);
    }
}
