//! Islands of a scene and a scene restricted to one of them.
//!
//! Elements join a body to a support, or two bodies (`Attachment::Relative`); contacts join two
//! bodies only while closed. So while every contact is open, the bodies joined by elements
//! (an *island*) move independently of every other island: each can be integrated alone on the
//! scene restricted to it, the open contacts between islands watched from outside.

use super::{Attachment, BodyRef, Scene};
use nalgebra::DVector;

/// A scene restricted to one island, with its indices into the whole scene.
#[derive(Clone, Debug)]
pub struct Restricted {
    /// The scene of the island's bodies (and every body without DOFs).
    pub scene: Scene,
    /// Whole-scene index of each DOF.
    pub dofs: Vec<usize>,
    /// Whole-scene index of each hysteretic element.
    pub hysteretic: Vec<usize>,
    /// Whole-scene index of each contact (those whose bodies are all in the island, or fixed).
    pub contacts: Vec<usize>,
}

impl Scene {
    /// The islands: bodies with DOFs joined by elements (union–find), each sorted, in the order
    /// of their first body. Bodies without DOFs (fixed or driven by the ground) belong to none.
    pub fn islands(&self) -> Vec<Vec<usize>> {
        let nb = self.bodies.len();
        let mut parent: Vec<usize> = (0..nb).collect();
        fn root(p: &mut [usize], mut i: usize) -> usize {
            while p[i] != i {
                p[i] = p[p[i]];
                i = p[i];
            }
            i
        }
        let attachments = (self.springs.iter().map(|s| &s.attachment))
            .chain(self.hysteretic.iter().map(|h| &h.attachment));
        for att in attachments {
            if let (a, Some(b)) = att.bodies() {
                let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
                parent[ra.max(rb)] = ra.min(rb);
            }
        }
        let mut out: Vec<Vec<usize>> = Vec::new();
        let mut slot = vec![usize::MAX; nb];
        for i in 0..nb {
            if self.bodies[i].has_no_dofs() {
                continue;
            }
            let r = root(&mut parent, i);
            if slot[r] == usize::MAX {
                slot[r] = out.len();
                out.push(Vec::new());
            }
            out[slot[r]].push(i);
        }
        out
    }

    /// The scene of the bodies `island` (from [`Scene::islands`]) and every body without DOFs:
    /// their elements, the contacts among them, the seats of those contacts, every support.
    /// DOFs, elements and contacts are numbered anew, in the whole scene's order.
    pub fn restrict(&self, island: &[usize]) -> Restricted {
        let nb = self.bodies.len();
        let kept: Vec<bool> = (0..nb)
            .map(|i| island.contains(&i) || self.bodies[i].has_no_dofs())
            .collect();
        let mut body_map = vec![usize::MAX; nb];
        let mut bodies = Vec::new();
        let mut dofs = Vec::new();
        for (i, b) in self.bodies.iter().enumerate() {
            if !kept[i] {
                continue;
            }
            body_map[i] = bodies.len();
            let mut b = b.clone();
            for d in b.dofs.iter_mut().flatten() {
                dofs.push(*d);
                *d = dofs.len() - 1;
            }
            bodies.push(b);
        }
        let mut dof_map = vec![usize::MAX; self.ndof()];
        for (k, &d) in dofs.iter().enumerate() {
            dof_map[d] = k;
        }
        let on = |att: &Attachment| {
            let (a, b) = att.bodies();
            kept[a] && b.is_none_or(|b| kept[b])
        };
        let moved = |att: &Attachment| {
            let mut att = att.clone();
            match &mut att {
                Attachment::Point { body, .. } | Attachment::Rotation { body } => {
                    *body = body_map[*body]
                }
                Attachment::Relative { body, other, .. } => {
                    *body = body_map[*body];
                    *other = body_map[*other];
                }
            }
            att
        };
        let body_ref = |r: BodyRef| match r {
            BodyRef::Ground => Some(BodyRef::Ground),
            BodyRef::Body(i) => kept[i].then(|| BodyRef::Body(body_map[i])),
        };
        let mut scene = self.clone();
        scene.bodies = bodies;
        scene.springs = (self.springs.iter())
            .filter(|s| on(&s.attachment))
            .map(|s| {
                let mut s = s.clone();
                s.attachment = moved(&s.attachment);
                s
            })
            .collect();
        let hysteretic: Vec<usize> = (0..self.hysteretic.len())
            .filter(|&j| on(&self.hysteretic[j].attachment))
            .collect();
        scene.hysteretic = (hysteretic.iter())
            .map(|&j| {
                let mut h = self.hysteretic[j].clone();
                h.attachment = moved(&h.attachment);
                h
            })
            .collect();
        let mut contacts = Vec::new();
        scene.contacts.clear();
        for (i, c) in self.contacts.iter().enumerate() {
            if let (Some(p), Some(f)) = (body_ref(c.point_body), body_ref(c.face_body)) {
                let mut c = c.clone();
                (c.point_body, c.face_body) = (p, f);
                scene.contacts.push(c);
                contacts.push(i);
            }
        }
        scene.seats = (self.seats.iter())
            .filter_map(|s| {
                let k = contacts.iter().position(|&i| i == s.contact)?;
                let mut s = s.clone();
                s.contact = k;
                Some(s)
            })
            .collect();
        scene.mass_damping.reference = (self.mass_damping.reference.iter())
            .filter(|&&(d, ..)| dof_map[d] != usize::MAX)
            .map(|&(d, s, f)| (dof_map[d], s, f))
            .collect();
        let pick =
            |v: &DVector<f64>| DVector::from_iterator(dofs.len(), dofs.iter().map(|&d| v[d]));
        scene.loads = pick(&self.loads);
        scene.mass = pick(&self.mass);
        scene.q0 = pick(&self.q0);
        scene.v0 = pick(&self.v0);
        scene.dof_names = dofs.iter().map(|&d| self.dof_names[d].clone()).collect();
        Restricted {
            scene,
            dofs,
            hysteretic,
            contacts,
        }
    }
}
