#include "host/scenario/field_problems.h"

#include <google/protobuf/reflection.h>

namespace hilrig::host {

using google::protobuf::FieldDescriptor;
using google::protobuf::Message;

void CheckEveryScalar(const Message& message, const ProblemList& problems,
                      const ScalarCheck& check) {
  const auto* reflection = message.GetReflection();
  std::vector<const FieldDescriptor*> fields;
  reflection->ListFields(message, &fields);
  for (const FieldDescriptor* field : fields) {
    const bool is_message = field->cpp_type() == FieldDescriptor::CPPTYPE_MESSAGE;
    if (field->is_repeated()) {
      for (int i = 0; i < reflection->FieldSize(message, field); ++i) {
        const ProblemList element = problems.Element(field->name(), i);
        if (is_message) {
          CheckEveryScalar(reflection->GetRepeatedMessage(message, field, i), element, check);
        } else if (auto problem = check(message, field, i)) {
          element.AddHere(std::move(*problem));
        }
      }
    } else if (is_message) {
      CheckEveryScalar(reflection->GetMessage(message, field), problems.Nested(field->name()),
                       check);
    } else if (auto problem = check(message, field, -1)) {
      problems.Add(field->name(), std::move(*problem));
    }
  }
}

}  // namespace hilrig::host
