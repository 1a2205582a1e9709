//! Links: planned from references to particles and groups, then made as springs
//! (forces) or rods and cables (contact generators).

use std::ops::Range;

use glam::Vec3;

use super::{
    Builder, End, Handle, Kind, LinkPlan, LinkRecord, Located, MAX_EVALUATIONS, MAX_LINKS, NON_NEGATIVE,
    POSITIVE, UNIT, kind_name,
};
use crate::messages::{clip, name_list as list};
use crate::physics::{Constraint, ForceGenerator, LinkEnd, Spring, StiffSpring};
use crate::scenes::file::format::{Document, LinkProps, Ref};

impl Builder<'_> {
    /// Plans links between members `first + a` and `first + b` of a group.
    pub(super) fn group_links(
        &mut self,
        kind: Kind,
        props: LinkProps<'_>,
        first: usize,
        pairs: &[(usize, usize)],
        span: &Range<usize>,
    ) -> Result<(), Located> {
        if kind == Kind::StiffSpring {
            return Err(Located::at(
                span,
                "a stiff spring joins a particle to an anchor; use it in a [[link]]",
            ));
        }
        let shared = self.props(props, kind)?;
        if shared.k.is_nan() {
            return Err(Located::at(span, format!("a {} needs `k` (N/m)", kind_name(kind))));
        }
        self.check_link_room(pairs.len(), span)?;
        for &(a, b) in pairs {
            self.plans.push(LinkPlan {
                a: first + a,
                b: End::Particle(first + b),
                span: span.clone(),
                ..shared
            });
        }
        Ok(())
    }

    /// Counts `each` terms for every one of `members`, refusing the table that takes the
    /// file past [`MAX_EVALUATIONS`] with what it costs.
    pub(super) fn spend_evaluations(
        &mut self,
        each: usize,
        members: usize,
        table: &str,
        span: &Range<usize>,
    ) -> Result<(), Located> {
        self.evaluations += each * members;
        if self.evaluations > MAX_EVALUATIONS {
            return Err(Located::at(
                span,
                format!(
                    "this {table} evaluates {each} expression terms for each of its {members} particles, \
                     which brings the file to {}; a scene file evaluates at most {MAX_EVALUATIONS} \
                     (shorten the expressions, or make fewer particles)",
                    self.evaluations
                ),
            ));
        }
        Ok(())
    }

    pub(super) fn check_link_room(&self, more: usize, span: &Range<usize>) -> Result<(), Located> {
        if self.plans.len() + more > MAX_LINKS {
            return Err(Located::at(span, format!("a scene file makes at most {MAX_LINKS} links")));
        }
        Ok(())
    }

    /// The properties every link of a group shares, checked for its kind.
    pub(super) fn props(&mut self, props: LinkProps<'_>, kind: Kind) -> Result<LinkPlan, Located> {
        let length = match props.length {
            Some(field) => {
                let value = self.compile(field, &[])?;
                let bounds =
                    if kind == Kind::Spring || kind == Kind::Bungee { NON_NEGATIVE } else { POSITIVE };
                Some(self.eval(&value, &[], "length", bounds)?)
            }
            None => None,
        };
        let springy = matches!(kind, Kind::Spring | Kind::Bungee | Kind::StiffSpring);
        let k = match (props.k, springy) {
            (Some(field), true) => {
                let value = self.compile(field, &[])?;
                let bounds = if kind == Kind::StiffSpring { POSITIVE } else { NON_NEGATIVE };
                self.eval(&value, &[], "k", bounds)?
            }
            // Missing: the caller says so at the table, where `k` belongs.
            (None, true) => f32::NAN,
            (Some(field), false) => {
                return Err(Located::at(&field.span(), "k is for springs, bungees and stiff springs"));
            }
            (None, false) => 0.0,
        };
        let restitution = self.compile_or(props.restitution, 0.0, &[])?;
        let restitution = self.eval(&restitution, &[], "restitution", UNIT)?;
        let damping_ratio = self.compile_or(props.damping_ratio, 0.0, &[])?;
        let damping_ratio = self.eval(&damping_ratio, &[], "damping_ratio", NON_NEGATIVE)?;
        let tear = match props.tear {
            Some(field) => {
                let value = self.compile(field, &[])?;
                Some(self.eval(&value, &[], "tear", POSITIVE)?)
            }
            None => None,
        };
        Ok(LinkPlan {
            kind,
            a: 0,
            b: End::Anchor(Vec3::ZERO),
            length,
            k,
            restitution,
            damping_ratio,
            tear,
            span: 0..0,
        })
    }

    /// The particles a reference names.
    pub(super) fn resolve(&self, field: &toml::Spanned<Ref>) -> Result<Vec<usize>, Located> {
        let span = field.span();
        let total = self.ids.len();
        match field.get_ref() {
            Ref::Index(k) => {
                if (0..total as i64).contains(k) {
                    Ok(vec![*k as usize])
                } else {
                    Err(Located::at(
                        &span,
                        format!(
                            "particle {k} is out of range: the file makes {total} particles (0 to {})",
                            total.saturating_sub(1)
                        ),
                    ))
                }
            }
            Ref::Name(text) => {
                let mut parts = text.split('.');
                let base = parts.next().unwrap_or("");
                let Some(group) = self.named.get(base).map(|&k| &self.groups[k]) else {
                    let valid = if self.named.is_empty() {
                        "none (give particles a name)".into()
                    } else {
                        list(self.groups.iter().filter_map(|g| g.name))
                    };
                    return Err(Located::at(
                        &span,
                        format!("no particle or array named '{}'; names: {valid}", clip(base, 40)),
                    ));
                };
                let indices: Vec<&str> = parts.collect();
                let member = |part: &str, len: usize| -> Result<usize, Located> {
                    let k: i64 = part.parse().map_err(|_| {
                        Located::at(
                            &span,
                            format!("'{}' in '{}' is not a whole number", clip(part, 24), clip(text, 40)),
                        )
                    })?;
                    let index = if k < 0 { k + len as i64 } else { k };
                    if (0..len as i64).contains(&index) {
                        Ok(index as usize)
                    } else {
                        Err(Located::at(
                            &span,
                            format!(
                                "index {k} of '{}' is out of range: it has {len} (0 to {})",
                                clip(base, 40),
                                len - 1
                            ),
                        ))
                    }
                };
                let single = group.single && indices.is_empty();
                match (indices.as_slice(), group.rows) {
                    ([], _) if single => Ok(vec![group.first]),
                    ([], _) => Ok((group.first..group.first + group.rows * group.cols).collect()),
                    ([k], 1) => Ok(vec![group.first + member(k, group.cols)?]),
                    ([i, j], _) => {
                        Ok(vec![group.first + member(i, group.rows)? * group.cols + member(j, group.cols)?])
                    }
                    ([_], _) => Err(Located::at(
                        &span,
                        format!("'{0}' is a grid: name a member as '{0}.ROW.COL'", clip(base, 40)),
                    )),
                    _ => Err(Located::at(&span, format!("'{}' has too many indices", clip(text, 40)))),
                }
            }
        }
    }

    pub(super) fn links(&mut self, doc: &Document) -> Result<(), Located> {
        for table in &doc.link {
            let span = table.span();
            let t = table.get_ref();
            let kind = Self::kind(&t.kind)?;
            let a = self.resolve(&t.a)?;
            let ends: Vec<End> = match (&t.b, &t.anchor) {
                (Some(b), None) => {
                    if kind == Kind::StiffSpring {
                        return Err(Located::at(
                            &b.span(),
                            "a stiff spring joins a particle to an `anchor`, not to `b`",
                        ));
                    }
                    self.resolve(b)?.into_iter().map(End::Particle).collect()
                }
                (None, Some(anchor)) => {
                    let anchor = self.compile_vec(anchor, &[])?;
                    vec![End::Anchor(self.eval_vec(&anchor, &[], "anchor")?)]
                }
                (Some(b), Some(_)) => return Err(Located::at(&b.span(), "give `b` or `anchor`, not both")),
                (None, None) => {
                    return Err(Located::at(&span, "a link needs `b` (a particle) or `anchor` ([x, y, z])"));
                }
            };
            let pairs: Vec<(usize, End)> = match (a.len(), ends.len()) {
                (_, 1) => a.iter().map(|&a| (a, ends[0])).collect(),
                (1, _) => ends.iter().map(|&b| (a[0], b)).collect(),
                (m, n) if m == n => a.iter().copied().zip(ends.iter().copied()).collect(),
                (m, n) => {
                    return Err(Located::at(
                        &span,
                        format!("`a` names {m} particles and `b` {n}: they must match"),
                    ));
                }
            };
            let mut shared = self.props(t.props(), kind)?;
            if shared.k.is_nan() {
                return Err(Located::at(&t.kind.span(), format!("a {} needs `k` (N/m)", t.kind.get_ref())));
            }
            shared.span = span.clone();
            self.check_link_room(pairs.len(), &span)?;
            for (a, b) in pairs {
                if let End::Particle(b) = b
                    && a == b
                {
                    return Err(Located::at(&span, format!("particle {a} is linked to itself")));
                }
                self.plans.push(LinkPlan { a, b, span: span.clone(), ..shared });
            }
        }
        Ok(())
    }

    /// Makes planned links: springs into the force registry, rods and cables as contact
    /// generators. Returns the records of both, each in the order made.
    pub(super) fn make_links<'p>(
        &mut self,
        plans: impl Iterator<Item = &'p LinkPlan>,
    ) -> Result<(Vec<LinkRecord>, Vec<LinkRecord>), Located> {
        let mut forces = Vec::new();
        let mut contacts = Vec::new();
        for plan in plans {
            let a = self.ids[plan.a];
            let pa = self.world.particles.positions()[plan.a];
            let (b, pb) = match plan.b {
                End::Particle(k) => (LinkEnd::Particle(self.ids[k]), self.world.particles.positions()[k]),
                End::Anchor(p) => (LinkEnd::Anchor(p), p),
            };
            let distance = pa.distance(pb);
            let length = plan.length.unwrap_or(distance);
            let fail = |e: crate::physics::PhysicsError| Located::at(&plan.span, e.to_string());
            match plan.kind {
                Kind::Rod | Kind::Cable => {
                    if length <= 0.0 {
                        return Err(Located::at(
                            &plan.span,
                            format!(
                                "a {} needs a length > 0 (its ends start {distance} m apart)",
                                kind_name(plan.kind)
                            ),
                        ));
                    }
                    let rigid = plan.kind == Kind::Rod;
                    let link = match b {
                        LinkEnd::Particle(b) if rigid => Constraint::rod(a, b, length),
                        LinkEnd::Particle(b) => Constraint::cable(a, b, length, plan.restitution),
                        LinkEnd::Anchor(p) if rigid => Constraint::support_rod(a, p, length),
                        LinkEnd::Anchor(p) => Constraint::support_cable(a, p, length, plan.restitution),
                    };
                    let spec = link.spec();
                    let id = self.world.add_contact_generator(link).map_err(fail)?;
                    contacts.push(LinkRecord { handle: Handle::Contact(id), spec, tear: plan.tear });
                }
                Kind::Spring | Kind::Bungee => {
                    let mut spring = Spring { a, b, k: plan.k, rest_length: length, bungee: false };
                    if plan.kind == Kind::Bungee {
                        spring = spring.as_bungee();
                    }
                    let spec = spring.link().expect("a spring is a link");
                    let id = self.world.add_force(spring).map_err(fail)?;
                    forces.push(LinkRecord { handle: Handle::Force(id), spec, tear: plan.tear });
                }
                Kind::StiffSpring => {
                    let LinkEnd::Anchor(anchor) = b else {
                        return Err(Located::at(&plan.span, "a stiff spring needs an `anchor`"));
                    };
                    let spring = StiffSpring::new(a, anchor, plan.k, plan.damping_ratio);
                    let spec = spring.link().expect("a stiff spring is a link");
                    let id = self.world.add_force(spring).map_err(fail)?;
                    forces.push(LinkRecord { handle: Handle::Force(id), spec, tear: plan.tear });
                }
            }
        }
        Ok((forces, contacts))
    }
}
