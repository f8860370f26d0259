//! The resting contacts that took an impulse at the current instant of a step's event loop,
//! so that a later resting impact at that same instant can be solved together with them.
//!
//! Resolved one after the other, a sphere wedged between a fixed sphere and a sphere pressing
//! on it passes the push back and forth, smaller each time, until what is left falls under the
//! creep speed and sinks the pair for the rest of the step. Solved together, the wedge takes
//! its load at once.
//!
//! It also counts the bounces each dynamic body takes at the instant, so that an inelastic
//! collapse there can be told (see `COLLAPSE_BOUNCES` in the solver).
//!
//! Contacts are kept in one list per dynamic body (a fixed body's velocity never changes, so
//! it joins nothing), so that finding a body's contacts and everything connected to them costs
//! what the bodies reached have recorded at this instant (contacts already gathered or
//! replaced are marked, and dropped from a list when it is next walked), however many contacts
//! the instant holds (a sheet of spheres landing at once makes tens of thousands).

/// The end of a body's list.
const NONE: u32 = u32::MAX;

/// One recorded contact: its bodies, and the next contact in each body's list.
#[derive(Clone, Copy, Debug)]
struct Link {
    pair: [u32; 2],
    next: [u32; 2],
    /// Already gathered into a group (or replaced by a new impact of the same pair).
    used: bool,
}

/// The current instant's resting contacts (see the module docs).
#[derive(Debug, Default)]
pub(crate) struct InstantContacts {
    time: f64,
    links: Vec<Link>,
    /// Each body's first link, valid when its epoch is `epoch`.
    heads: Vec<(u32, u32)>,
    epoch: u32,
    /// Bodies reached by the current [`InstantContacts::gather`], valid when their mark is
    /// `seen_epoch`.
    seen: Vec<u32>,
    seen_epoch: u32,
    reached: Vec<u32>,
    /// Each dynamic body's bounces at this instant (see [`InstantContacts::bounced`]), valid
    /// when its epoch is `epoch`.
    bounces: Vec<(u32, u32)>,
    /// The most bounces any body took at this instant (each body's counted from the
    /// instant's [`InstantContacts::COUNT_FROM`]th).
    most_bounces: u32,
    /// Bounces at this instant, all bodies'.
    all_bounces: u32,
    /// The fastest approach of a bounce at this instant.
    fastest: f64,
}

impl InstantContacts {
    /// Forgets every contact: a new instant starts at `time`, with bodies indexed below
    /// `bodies`.
    pub(crate) fn start(&mut self, time: f64, bodies: usize) {
        self.time = time;
        self.links.clear();
        self.most_bounces = 0;
        self.all_bounces = 0;
        self.fastest = 0.0;
        self.epoch = self.epoch.wrapping_add(1);
        if self.epoch == 0 {
            self.heads.iter_mut().for_each(|h| *h = (0, NONE));
            self.bounces.iter_mut().for_each(|b| *b = (0, 0));
            self.epoch = 1;
        }
        if self.heads.len() < bodies {
            self.heads.resize(bodies, (0, NONE));
            self.seen.resize(bodies, 0);
            self.bounces.resize(bodies, (0, 0));
        }
    }

    /// Whether no contact was recorded at this instant (the usual case: then nothing joins).
    pub(crate) fn is_empty(&self) -> bool {
        self.links.is_empty()
    }

    /// When the current instant started.
    pub(crate) fn time(&self) -> f64 {
        self.time
    }

    fn head(&self, k: u32) -> u32 {
        match self.heads[k as usize] {
            (epoch, head) if epoch == self.epoch => head,
            _ => NONE,
        }
    }

    /// Records a resting contact between `a` and `b` (listed under each that `moves`),
    /// replacing the pair's earlier one at this instant.
    pub(crate) fn record(&mut self, a: u32, b: u32, moves: impl Fn(u32) -> bool) {
        self.replace(a, b, &moves);
        let index = self.links.len() as u32;
        let mut link = Link {
            pair: [a, b],
            next: [NONE; 2],
            used: false,
        };
        for (end, k) in [a, b].into_iter().enumerate() {
            if moves(k) {
                link.next[end] = self.head(k);
                self.heads[k as usize] = (self.epoch, index);
            }
        }
        self.links.push(link);
    }

    /// Counts an impact with restitution (a bounce, not a resting impact) at this instant
    /// between bodies `a` and `b`, approaching at `speed`, for each of them that `moves`.
    /// Bodies' own counts start at the instant's [`InstantContacts::COUNT_FROM`]th bounce:
    /// most instants take one or two, and are spared the bookkeeping.
    #[inline(always)]
    pub(crate) fn bounced(&mut self, a: u32, b: u32, speed: f64, moves: impl Fn(u32) -> bool) {
        self.fastest = self.fastest.max(speed);
        self.all_bounces = self.all_bounces.saturating_add(1);
        if self.all_bounces >= Self::COUNT_FROM {
            self.count_both(a, b, moves);
        }
    }

    #[cold]
    #[inline(never)]
    fn count_both(&mut self, a: u32, b: u32, moves: impl Fn(u32) -> bool) {
        for k in [a, b] {
            if moves(k) {
                self.count(k);
            }
        }
    }

    /// The bounce of an instant from which each body's are counted.
    pub(crate) const COUNT_FROM: u32 = 16;

    fn count(&mut self, k: u32) {
        let epoch = self.epoch;
        if let Some(slot) = self.bounces.get_mut(k as usize) {
            *slot = match *slot {
                (e, n) if e == epoch => (epoch, n.saturating_add(1)),
                _ => (epoch, 1),
            };
            self.most_bounces = self.most_bounces.max(slot.1);
        }
    }

    /// The fastest approach of a bounce at this instant (0 before any).
    pub(crate) fn fastest(&self) -> f64 {
        self.fastest
    }

    /// The most bounces any body took at this instant.
    pub(crate) fn most_bounces(&self) -> u32 {
        self.most_bounces
    }

    /// How many bounces dynamic body `k` took at this instant, counted from the instant's
    /// [`InstantContacts::COUNT_FROM`]th.
    pub(crate) fn bounces(&self, k: u32) -> u32 {
        match self.bounces.get(k as usize) {
            Some(&(e, n)) if e == self.epoch => n,
            _ => 0,
        }
    }

    /// Whether dynamic body `k` has a contact at this instant that may still be gathered (or
    /// a used one its list has not dropped yet).
    pub(crate) fn involves(&self, k: u32) -> bool {
        self.head(k) != NONE
    }

    /// Marks the contacts of pair `(a, b)` as replaced (a new impact of theirs is being solved).
    pub(crate) fn replace(&mut self, a: u32, b: u32, moves: impl Fn(u32) -> bool) {
        let owner = if moves(a) { a } else { b };
        let mut prev = NONE;
        let mut index = self.head(owner);
        while index != NONE {
            let link = &mut self.links[index as usize];
            let next = link.next[usize::from(link.pair[0] != owner)];
            if link.pair == [a, b] || link.pair == [b, a] {
                link.used = true;
            }
            if link.used {
                self.unlink(owner, prev, next);
            } else {
                prev = index;
            }
            index = next;
        }
    }

    /// Takes the link after `prev` (or the first, if `prev` is [`NONE`]) out of body `k`'s
    /// list, `next` following `prev` instead: a used link stays where it is in the other
    /// body's list, until that list is walked. (Kept, used links were walked again and again:
    /// in a landing pit nine in ten of the links the walks read.)
    fn unlink(&mut self, k: u32, prev: u32, next: u32) {
        if prev == NONE {
            self.heads[k as usize] = (self.epoch, next);
        } else {
            let link = &mut self.links[prev as usize];
            link.next[usize::from(link.pair[0] != k)] = next;
        }
    }

    /// Gathers every unused contact connected to the dynamic bodies among `seeds` (through
    /// dynamic bodies), marking them used and handing each pair to `take`. The dynamic bodies
    /// reached, seeds included, are then in [`InstantContacts::reached`].
    pub(crate) fn gather(
        &mut self,
        seeds: impl Iterator<Item = u32>,
        moves: impl Fn(u32) -> bool,
        mut take: impl FnMut(u32, u32),
    ) {
        self.seen_epoch = self.seen_epoch.wrapping_add(1);
        if self.seen_epoch == 0 {
            self.seen.iter_mut().for_each(|s| *s = 0);
            self.seen_epoch = 1;
        }
        self.reached.clear();
        for k in seeds {
            self.reach(k, &moves);
        }
        let mut next = 0;
        while next < self.reached.len() {
            let k = self.reached[next];
            next += 1;
            // Every link of `k`'s is used after this walk: each is taken out of its list.
            let mut index = self.head(k);
            while index != NONE {
                let link = self.links[index as usize];
                if !link.used {
                    self.links[index as usize].used = true;
                    take(link.pair[0], link.pair[1]);
                    for m in link.pair {
                        self.reach(m, &moves);
                    }
                }
                index = link.next[usize::from(link.pair[0] != k)];
            }
            self.heads[k as usize] = (self.epoch, NONE);
        }
    }

    fn reach(&mut self, k: u32, moves: impl Fn(u32) -> bool) {
        if moves(k) && self.seen[k as usize] != self.seen_epoch {
            self.seen[k as usize] = self.seen_epoch;
            self.reached.push(k);
        }
    }

    /// The dynamic bodies the last [`InstantContacts::gather`] reached.
    pub(crate) fn reached(&self) -> &[u32] {
        &self.reached
    }
}
