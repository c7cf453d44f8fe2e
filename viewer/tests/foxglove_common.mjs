// Shared by the Foxglove tests: the channels sgslam publishes (docs/foxglove.md)
// and a check of a message against its channel's JSON Schema.

export const EXPECTED = {
  '/tf': 'foxglove.FrameTransform',
  '/camera/pose': 'foxglove.PoseInFrame',
  '/camera/image': 'foxglove.CompressedImage',
  '/camera/calibration': 'foxglove.CameraCalibration',
  '/camera/annotations': 'foxglove.ImageAnnotations',
  '/movers': 'foxglove.SceneUpdate',
  '/stats': 'sgslam.FrameStats',
  '/map/trajectory': 'foxglove.PosesInFrame',
  '/map/points': 'foxglove.PointCloud',
  '/map/cloud': 'foxglove.PointCloud',
  '/map/objects': 'foxglove.SceneUpdate',
};

// The JSON Schema rules Foxglove's schemas use: type, properties, required, items,
// oneOf of consts (enums), minimum/maximum, base64 content. Appends what is wrong.
export function validate(schema, value, where, errors) {
  if (errors.length > 5) return;
  if (schema.oneOf) {
    if (!schema.oneOf.some((o) => o.const === value)) errors.push(`${where}: ${value} is none of ${schema.title}`);
    return;
  }
  const type = schema.type;
  const is = {
    object: (v) => v !== null && typeof v === 'object' && !Array.isArray(v),
    array: Array.isArray,
    string: (v) => typeof v === 'string',
    number: (v) => typeof v === 'number' && Number.isFinite(v),
    integer: Number.isInteger,
    boolean: (v) => typeof v === 'boolean',
  };
  if (type && !is[type](value)) { errors.push(`${where}: not a ${type} (${JSON.stringify(value)?.slice(0, 40)})`); return; }
  if (schema.minimum !== undefined && value < schema.minimum) errors.push(`${where}: ${value} < ${schema.minimum}`);
  if (schema.maximum !== undefined && value > schema.maximum) errors.push(`${where}: ${value} > ${schema.maximum}`);
  if (schema.contentEncoding === 'base64' && !/^[A-Za-z0-9+/]*={0,2}$/.test(value)) errors.push(`${where}: not base64`);
  if (type === 'object') {
    for (const key of schema.required ?? []) if (!(key in value)) errors.push(`${where}.${key}: missing`);
    for (const [key, v] of Object.entries(value)) {
      if (!schema.properties?.[key]) { errors.push(`${where}.${key}: not in the schema`); continue; }
      validate(schema.properties[key], v, `${where}.${key}`, errors);
    }
  }
  if (type === 'array') {
    if (schema.minItems !== undefined && value.length < schema.minItems) errors.push(`${where}: fewer than ${schema.minItems} items`);
    if (schema.maxItems !== undefined && value.length > schema.maxItems) errors.push(`${where}: more than ${schema.maxItems} items`);
    if (schema.items) value.forEach((v, i) => validate(schema.items, v, `${where}[${i}]`, errors));
  }
}

