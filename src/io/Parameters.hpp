#pragma once
// The scene file: one Teuchos ParameterList read from XML, overridden by
// --set, validated against the full list of valid parameters (types, ranges,
// documentation). Turning the list into a SceneConfig is the scene
// builder's (scene/SceneBuilder.hpp).
#include <Teuchos_ParameterList.hpp>
#include <Teuchos_RCP.hpp>

#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

namespace poresph {

// Raised for anything wrong with the input; the message names the parameter.
struct ParameterError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Every parameter PoreSPH accepts, with default, type, range and documentation.
Teuchos::RCP<const Teuchos::ParameterList> valid_parameters();

void print_valid_parameters(std::ostream& os);

// "Sublist/Parameter Name=value" applied to `list`; the type comes from the
// valid list, so an unknown path is an error naming it. Returns the path.
std::string apply_override(Teuchos::ParameterList& list, const std::string& assignment);

// Reads `xml_file`, applies the overrides, checks required values and
// validates (filling in defaults). Throws ParameterError.
Teuchos::RCP<Teuchos::ParameterList> read_parameters(const std::string& xml_file,
                                                     const std::vector<std::string>& overrides);

// Validates an in-memory list the same way (used by read_parameters and tests).
void validate_parameters(Teuchos::ParameterList& list);

void write_parameters_xml(const Teuchos::ParameterList& list, const std::string& file);
// The list as Teuchos XML text.
std::string parameters_to_xml(const Teuchos::ParameterList& list);

}  // namespace poresph
