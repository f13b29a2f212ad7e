#include "host/scenario/field_path.h"

#include <google/protobuf/descriptor.h>

#include <cctype>
#include <cmath>
#include <limits>
#include <optional>

#include "rig/number_text.h"

namespace hilrig::host {
namespace {

using google::protobuf::Descriptor;
using google::protobuf::FieldDescriptor;
using google::protobuf::Message;
using google::protobuf::Reflection;

bool IsNameCharacter(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

rig::Result<FieldPathPart> ParsePart(const std::string& text) {
  FieldPathPart part;
  const std::size_t bracket = text.find('[');
  part.name = text.substr(0, bracket);
  if (part.name.empty()) return rig::MakeError("an empty field name");
  for (const char c : part.name) {
    if (!IsNameCharacter(c)) return rig::MakeError("\"" + part.name + "\" is no field name");
  }
  if (bracket == std::string::npos) return part;
  const std::string index = text.substr(bracket + 1);
  if (index.size() < 2 || index.back() != ']') {
    return rig::MakeError("\"" + text + "\": expected NAME[INDEX]");
  }
  const std::string digits = index.substr(0, index.size() - 1);
  if (digits.size() > 6 || digits.find_first_not_of("0123456789") != std::string::npos) {
    return rig::MakeError("\"" + text + "\": the index must be a whole number below 1000000");
  }
  part.index = std::stoi(digits);
  return part;
}

// Where a path ends: the message that holds the last field, and that field.
struct Target {
  const Message* holder = nullptr;
  const FieldDescriptor* field = nullptr;
};

// Walks `path` over `message` without changing it (an unset message field reads as its default
// instance); `walked` names the parts that were fine, for the error.
rig::Result<Target> Walk(const Message& message, const std::vector<FieldPathPart>& parts) {
  const Message* current = &message;
  std::string walked;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const FieldPathPart& part = parts[i];
    const Descriptor* descriptor = current->GetDescriptor();
    const FieldDescriptor* field = descriptor->FindFieldByName(part.name);
    const std::string here = walked.empty() ? part.name : walked + "." + part.name;
    const auto fail = [&here](const std::string& why) { return rig::MakeError(here + ": " + why); };
    if (field == nullptr) return fail(descriptor->name() + " has no field " + part.name);
    const Reflection* reflection = current->GetReflection();
    if (field->is_repeated() != (part.index >= 0)) {
      return fail(field->is_repeated() ? "a repeated field: name an element, " + part.name + "[N]"
                                       : "not a repeated field: it takes no index");
    }
    if (field->is_repeated() && part.index >= reflection->FieldSize(*current, field)) {
      return fail("no element " + std::to_string(part.index) + " (the spec has " +
                  std::to_string(reflection->FieldSize(*current, field)) + ")");
    }
    if (const auto* oneof = field->real_containing_oneof()) {
      const FieldDescriptor* set = reflection->GetOneofFieldDescriptor(*current, oneof);
      if (set != nullptr && set != field) {
        return fail("this " + descriptor->name() + " holds " + set->name() + ", not " +
                    field->name());
      }
    }
    const bool last = i + 1 == parts.size();
    if (last) return Target{current, field};
    if (field->cpp_type() != FieldDescriptor::CPPTYPE_MESSAGE) {
      return fail("a number, not a message: the path ends here");
    }
    current = field->is_repeated() ? &reflection->GetRepeatedMessage(*current, field, part.index)
                                   : &reflection->GetMessage(*current, field);
    walked = here;
    if (part.index >= 0) walked.append("[").append(std::to_string(part.index)).append("]");
  }
  return rig::MakeError("an empty path");
}

rig::Result<void> CheckNumberField(const FieldDescriptor& field) {
  switch (field.cpp_type()) {
    case FieldDescriptor::CPPTYPE_STRING:
      return rig::MakeError(field.name() + " is text, not a number");
    case FieldDescriptor::CPPTYPE_MESSAGE:
      return rig::MakeError(field.name() + " is a message (" + field.message_type()->name() +
                            "), not a number: name one of its fields");
    default:
      return {};
  }
}

// A value comes as a double, which holds every whole number up to 2^53 exactly and no larger one
// for sure: 2^64 - 1 reads as 2^64, which no uint64 holds (the cast would give 0). So a whole
// number fits when it is in the type's range and at most 2^53 in size.
template <typename Int>
bool FitsInteger(double value) {
  constexpr double kExactUpTo = 9007199254740992.0;                        // 2^53
  const double below = std::ldexp(1.0, std::numeric_limits<Int>::digits);  // max + 1, exact
  return value == std::floor(value) && value >= double(std::numeric_limits<Int>::min()) &&
         value < below && std::abs(value) <= kExactUpTo;
}

// Why `value` does not fit `field`; nothing when it does.
std::optional<std::string> ValueProblem(const FieldDescriptor& field, double value) {
  if (!std::isfinite(value)) return "not a finite number";
  switch (field.cpp_type()) {
    case FieldDescriptor::CPPTYPE_DOUBLE:
      return std::nullopt;
    case FieldDescriptor::CPPTYPE_FLOAT:
      if (std::abs(value) > std::numeric_limits<float>::max()) return "out of a float's range";
      return std::nullopt;
    case FieldDescriptor::CPPTYPE_INT32:
      if (!FitsInteger<std::int32_t>(value)) return "not a whole number in int32's range";
      return std::nullopt;
    case FieldDescriptor::CPPTYPE_INT64:
      if (!FitsInteger<std::int64_t>(value)) {
        return "not a whole number in int64's range that a double holds exactly (|n| <= 2^53)";
      }
      return std::nullopt;
    case FieldDescriptor::CPPTYPE_UINT32:
      if (!FitsInteger<std::uint32_t>(value)) return "not a whole number in uint32's range";
      return std::nullopt;
    case FieldDescriptor::CPPTYPE_UINT64:
      if (!FitsInteger<std::uint64_t>(value)) {
        return "not a whole number in uint64's range that a double holds exactly (n <= 2^53)";
      }
      return std::nullopt;
    case FieldDescriptor::CPPTYPE_BOOL:
      if (value != 0 && value != 1) return "a bool takes 0 or 1";
      return std::nullopt;
    case FieldDescriptor::CPPTYPE_ENUM:
      if (!FitsInteger<std::int32_t>(value) ||
          field.enum_type()->FindValueByNumber(static_cast<int>(value)) == nullptr) {
        return "not a number of " + field.enum_type()->name();
      }
      return std::nullopt;
    default:
      return "not a number field";
  }
}

void SetNumber(Message& holder, const FieldDescriptor& field, double value) {
  const Reflection* reflection = holder.GetReflection();
  switch (field.cpp_type()) {
    case FieldDescriptor::CPPTYPE_DOUBLE:
      return reflection->SetDouble(&holder, &field, value);
    case FieldDescriptor::CPPTYPE_FLOAT:
      return reflection->SetFloat(&holder, &field, static_cast<float>(value));
    case FieldDescriptor::CPPTYPE_INT32:
      return reflection->SetInt32(&holder, &field, static_cast<std::int32_t>(value));
    case FieldDescriptor::CPPTYPE_INT64:
      return reflection->SetInt64(&holder, &field, static_cast<std::int64_t>(value));
    case FieldDescriptor::CPPTYPE_UINT32:
      return reflection->SetUInt32(&holder, &field, static_cast<std::uint32_t>(value));
    case FieldDescriptor::CPPTYPE_UINT64:
      return reflection->SetUInt64(&holder, &field, static_cast<std::uint64_t>(value));
    case FieldDescriptor::CPPTYPE_BOOL:
      return reflection->SetBool(&holder, &field, value != 0);
    case FieldDescriptor::CPPTYPE_ENUM:
      return reflection->SetEnumValue(&holder, &field, static_cast<int>(value));
    default:
      return;  // refused by CheckNumberField before
  }
}

// The message that holds the path's last field, each message on the way made present.
Message& MutableHolder(Message& message, const std::vector<FieldPathPart>& parts) {
  Message* current = &message;
  for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
    const FieldDescriptor* field = current->GetDescriptor()->FindFieldByName(parts[i].name);
    const Reflection* reflection = current->GetReflection();
    current = field->is_repeated()
                  ? reflection->MutableRepeatedMessage(current, field, parts[i].index)
                  : reflection->MutableMessage(current, field);
  }
  return *current;
}

rig::Result<std::vector<FieldPathPart>> CheckedPath(const Message& message, const std::string& path,
                                                    const FieldDescriptor** field) {
  auto parts = ParseFieldPath(path);
  if (!parts) return parts.error();
  auto target = Walk(message, parts.value());
  if (!target) return rig::InContext("\"" + path + "\": ", target.error());
  if (auto number = CheckNumberField(*target.value().field); !number.ok()) {
    return rig::InContext("\"" + path + "\": ", number.error());
  }
  *field = target.value().field;
  return parts;
}

}  // namespace

rig::Result<std::vector<FieldPathPart>> ParseFieldPath(const std::string& path) {
  std::vector<FieldPathPart> parts;
  std::size_t start = 0;
  while (true) {
    const std::size_t dot = path.find('.', start);
    auto part = ParsePart(path.substr(start, dot == std::string::npos ? dot : dot - start));
    if (!part) return rig::InContext("field path \"" + path + "\": ", part.error());
    parts.push_back(std::move(part).value());
    if (dot == std::string::npos) return parts;
    start = dot + 1;
  }
}

rig::Result<void> CheckNumberPath(const Message& message, const std::string& path) {
  const FieldDescriptor* field = nullptr;
  auto parts = CheckedPath(message, path, &field);
  if (!parts) return parts.error();
  return {};
}

rig::Result<void> SetNumberAt(Message& message, const std::string& path, double value) {
  const FieldDescriptor* field = nullptr;
  auto parts = CheckedPath(message, path, &field);
  if (!parts) return parts.error();
  if (const auto problem = ValueProblem(*field, value)) {
    return rig::MakeError("\"" + path + "\" = " + rig::NumberText(value) + ": " + *problem);
  }
  SetNumber(MutableHolder(message, parts.value()), *field, value);
  return {};
}

}  // namespace hilrig::host
