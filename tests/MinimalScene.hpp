#pragma once
// The smallest scene parameter list that validates (a 2D periodic cell of
// fluid under a body force), for tests to change one thing in; and a
// Teuchos array from a brace list.
#include <Teuchos_Array.hpp>
#include <Teuchos_ParameterList.hpp>

#include <initializer_list>
#include <vector>

namespace poresph::testing {

// Teuchos::Array has no initializer-list constructor ({a, b} would pick the
// iterator-pair one): go through std::vector.
template <class T>
Teuchos::Array<T> array(std::initializer_list<T> values) {
  return Teuchos::Array<T>(std::vector<T>(values));
}

inline Teuchos::ParameterList minimal_scene() {
  Teuchos::ParameterList list("PoreSPH");
  list.sublist("Domain").set("Cell Size", array<double>({1.0, 1.0}));
  list.sublist("Fluid").set("Kinematic Viscosity", 1e-2);
  list.sublist("Fluid").set("Body Force", array<double>({1e-3, 0.0}));
  list.sublist("Discretization").set("Particle Spacing", 0.05);
  list.sublist("Run").set("End Time", 1.0);
  return list;
}

}  // namespace poresph::testing
